// core: the work budget's one check and its refusal line (issue 12 §1), and Ctrl-C removing the
// temporary file of an output being written (interrupt.hpp).
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/budget.hpp"
#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <limits>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using millnet::WorkEstimate;
using millnet::WorkLimits;

namespace {
std::string refusal(const WorkEstimate& e, const WorkLimits& l) {
  try {
    millnet::check_work(e, l);
  } catch (const millnet::Error& x) {
    return x.what();
  }
  return "";
}
}  // namespace

TEST(Budget, CountsAndBytesAreFormattedShort) {
  EXPECT_EQ(millnet::format_count(1e10), "1.0e10");
  EXPECT_EQ(millnet::format_count(2e7), "2.0e7");
  EXPECT_EQ(millnet::format_count(10201), "1.0e4");
  EXPECT_EQ(millnet::format_count(0.002), "2.0e-3");
  EXPECT_EQ(millnet::format_bytes(2.4e11), "240 GB");
  EXPECT_EQ(millnet::format_bytes(3.1e6), "3.1 MB");
  EXPECT_EQ(millnet::format_bytes(512), "512 B");
}

TEST(Budget, TheIssueExampleIsRefusedInOneLineNamingParameterEstimateAndLimit) {
  const WorkEstimate e{"stepover 0.001 mm over a 100 × 100 mm pocket", 1e10, "tool points", 2.4e11};
  const std::string msg = refusal(e, WorkLimits{});
  EXPECT_EQ(msg,
            "stepover 0.001 mm over a 100 × 100 mm pocket makes 1.0e10 tool points (≈ 240 GB); the limit is 2.0e7 "
            "(--max-work, /limits/max_work)");
}

TEST(Budget, AtTheLimitPassesJustAboveIsRefused) {
  const WorkLimits l{1000, 1048576};
  EXPECT_EQ(refusal({"x", 1000, "points", 1e6}, l), "");
  EXPECT_NE(
      refusal({"x", 1001, "points", 10}, l).find("makes 1.001e3 points (≈ 10 B); the limit is 1.000e3 (--max-work"),
      std::string::npos);
  const std::string mem = refusal({"cell 0.1 mm", 10, "cells", 2e6}, l);
  EXPECT_NE(mem.find("(≈ 2.0 MB); the memory limit is 1 MiB (--max-memory-mb, /limits/max_memory_mb)"),
            std::string::npos)
      << mem;
}

TEST(Budget, NaNAndInfinityAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal({"x", nan, "points", 0}, WorkLimits{}), "");
  EXPECT_NE(refusal({"x", inf, "points", 0}, WorkLimits{}), "");
  EXPECT_NE(refusal({"x", 1, "points", inf}, WorkLimits{}), "");
}

TEST(Budget, MemoryOnlyEstimatesIgnoreTheCountLimit) {
  WorkEstimate e{"cell_mm 0.01 mm over a 100 × 100 mm z-map", 1e8, "z-map cells", 1.2e9};
  e.memory_only = true;
  EXPECT_EQ(refusal(e, WorkLimits{}), "");
  e.bytes = 1e10;
  EXPECT_NE(refusal(e, WorkLimits{}).find("memory limit"), std::string::npos);
}

// A process interrupted while an output is half-written: the temporary file is removed, the final
// name never appears, and the process ends by the signal (re-raised with the default action).
class Interrupt : public ::testing::TestWithParam<int> {};

TEST_P(Interrupt, RemovesThePendingTemporaryFileAndEndsByTheSignal) {
  const int sig = GetParam();
  const fs::path d = fs::path(MILLNET_BINARY_DIR) / "test_tmp" / ("interrupt_" + std::to_string(sig));
  fs::remove_all(d);
  fs::create_directories(d);
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::close(ready[0]);
    millnet::AtomicOFStream out(d / "result.nc");
    out << "G0 X0 Y0\nG1 X1";  // half a program
    out.stream().flush();
    const char c = 'r';
    (void)!::write(ready[1], &c, 1);
    for (;;) ::pause();  // until the signal
  }
  ::close(ready[1]);
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ::close(ready[0]);
  std::size_t before = 0;
  for (const auto& e : fs::directory_iterator(d))
    before += e.path().filename().string().find(".tmp-") != std::string::npos;
  EXPECT_EQ(before, 1U) << "the child should be writing a temporary file";
  ASSERT_EQ(::kill(pid, sig), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status));
  if (WIFSIGNALED(status)) {
    EXPECT_EQ(WTERMSIG(status), sig);
  }
  std::string left;
  for (const auto& e : fs::directory_iterator(d)) left += e.path().filename().string() + " ";
  EXPECT_EQ(left, "");
}

INSTANTIATE_TEST_SUITE_P(Signals, Interrupt, ::testing::Values(SIGINT, SIGTERM));
