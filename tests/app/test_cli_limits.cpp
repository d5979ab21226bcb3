// Work limits through the executable (issue 12 §1): a small pocket just over a lowered --max-work is
// refused in one line and runs once the limit is raised to its estimate (so a guard stricter than
// its estimate fails here); /limits in a config does the same; Ctrl-C during a long run leaves no
// file behind. The refusals of the two issue examples and of every other guarded stage are whole
// runs in tests/corpus/cli/limits_*.args (exit 1, one line, nothing written, peak RSS < 1 GB).
#include "cli_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {
namespace fs = std::filesystem;
using millnet::testing::fresh_dir;
using millnet::testing::list_files;
using millnet::testing::run_millnet;

const std::string kSquare = std::string(MILLNET_SOURCE_DIR) + "/tests/corpus/cli/square100.json";
}  // namespace

// 100 mm square, D 10, stepover 1: 101² = 10,201 tool-point grid points, 20,402 SOM ring nodes and
// 112² = 12,544 feed-map cells (tests/pocket/test_work.cpp).
TEST(CliLimits, MaxWorkBelowTheEstimateRefusesAndAtTheEstimateRuns) {
  const fs::path d = fresh_dir("cli_limits/max_work");
  const std::string base = "pocket --pocket '" + kSquare + "' --stepover 1 --tool-diameter 10 --quiet --out out";
  const auto refused = run_millnet(base + " --max-work 20401", d, 60);
  EXPECT_EQ(refused.code, 1) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_NE(refused.err.find("millnet pocket: error: node_factor 2 × the tool points of stepover 1 mm over a 100 × 100 "
                             "mm pocket makes 2.0402e4 SOM ring nodes (≈ 653 kB); the limit is 2.0401e4 (--max-work, "
                             "/limits/max_work)"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(list_files(d / "out"), "");
  const auto ran = run_millnet(base + " --max-work 20402", d, 120);
  EXPECT_EQ(ran.code, 0) << ran.err;
  EXPECT_TRUE(fs::exists(d / "out" / "square100.nc"));
}

TEST(CliLimits, TheConfigSectionSetsTheLimitAndTheFlagWins) {
  const fs::path d = fresh_dir("cli_limits/config");
  std::ofstream(d / "c.json") << R"({"limits": {"max_work": 12000, "max_memory_mb": 4096}})";
  const std::string base =
      "pocket --pocket '" + kSquare + "' --stepover 1 --tool-diameter 10 --quiet --config c.json --out out";
  const auto refused = run_millnet(base, d, 60);
  EXPECT_EQ(refused.code, 1) << refused.err;
  EXPECT_NE(refused.err.find("the limit is 1.2e4 (--max-work, /limits/max_work)"), std::string::npos) << refused.err;
  // Stepover 0.25: 401² grid points × 24 B = 3.9 MB, over 1 MiB; the count 160,801 is within 1e6.
  const auto mem = run_millnet("pocket --pocket '" + kSquare +
                                   "' --stepover 0.25 --tool-diameter 10 --quiet --config "
                                   "c.json --max-work 1e6 --max-memory-mb 1 --out out",
                               d, 60);
  EXPECT_EQ(mem.code, 1) << mem.err;
  EXPECT_NE(mem.err.find("makes 1.6e5 tool points (≈ 3.9 MB); the memory limit is 1 MiB (--max-memory-mb, "
                         "/limits/max_memory_mb)"),
            std::string::npos)
      << mem.err;
  EXPECT_EQ(list_files(d / "out"), "");
}

TEST(CliLimits, OutOfRangeLimitFlagsAreRefusedNamingTheRange) {
  const fs::path d = fresh_dir("cli_limits/flags");
  const auto r = run_millnet("pocket --pocket '" + kSquare + "' --max-work nan --out out", d, 60);
  EXPECT_EQ(r.code, 1) << r.err;  // a value out of its key's range, as --stepover nan (tests/corpus/cli)
  EXPECT_NE(r.err.find("--max-work: expected a finite number ≥ 1 and ≤ 1000000000000 (/limits/max_work), got nan"),
            std::string::npos)
      << r.err;
}

// Ctrl-C in the middle of a long pocket (stepover 0.1: ~10⁶ grid points, a SOM run of many seconds):
// the run ends by the signal (or non-zero) and leaves no file, temporary or final. No timing is
// asserted: the signal is sent once the run has begun, whenever that is.
TEST(CliLimits, InterruptLeavesNoFile) {
  const fs::path d = fresh_dir("cli_limits/interrupt");
  const fs::path out = d / "out";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(MILLNET_EXE, MILLNET_EXE, "pocket", "--pocket", kSquare.c_str(), "--stepover", "0.1", "--tool-diameter",
            "10", "--threads", "1", "--out", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  const bool by_signal = WIFSIGNALED(status) && WTERMSIG(status) == SIGINT;
  const bool failed = WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 127;
  EXPECT_TRUE(by_signal || failed) << "status " << status;
  EXPECT_EQ(list_files(out), "");
}

// Issue 42 §9: `ulimit -f` ended the process by SIGXFSZ with 1–6 `.tmp` files left. The file-size
// limit now reads like a full disk: exit 1, one line naming the file and the limit, no file at all.
// 16 KiB: the pocket's tool points fit, its feed profile (square100.feed.csv) does not.
TEST(CliLimits, FileSizeLimitIsAWriteErrorAndLeavesNoFile) {
  const fs::path d = fresh_dir("cli_limits/ulimit_f");
  const std::string cmd = "cd '" + d.string() + "' && bash -c \"ulimit -f 16; exec '" + std::string(MILLNET_EXE) +
                          "' pocket --pocket '" + kSquare + "' --tool-diameter 10 --quiet --out out\" >cli.stdout " +
                          "2>cli.stderr </dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "status " << status;
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = millnet::testing::slurp(d / "cli.stderr");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("write failed: the file would exceed the file-size limit (ulimit -f)"), std::string::npos) << err;
  EXPECT_EQ(list_files(d / "out"), "");
}
