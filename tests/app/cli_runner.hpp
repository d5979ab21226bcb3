#pragma once
// Runs the millnet executable as a user would and captures its exit code and stderr.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace millnet::testing {

struct CliResult {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// `args` is appended to the executable path as shell words (callers quote what needs quoting).
/// With timeout_s > 0 the run is killed after that many seconds (exit code 124).
/// With memory_kib > 0 the run's address space is limited to that many KiB (`ulimit -v`).
inline CliResult run_millnet(const std::string& args, const std::filesystem::path& workdir, int timeout_s = 0,
                             long memory_kib = 0) {
  std::filesystem::create_directories(workdir);
  const auto out = workdir / "cli.stdout", err = workdir / "cli.stderr";
  const std::string limit = timeout_s > 0 ? "timeout -k 5 " + std::to_string(timeout_s) + " " : "";
  const std::string ulimit = memory_kib > 0 ? "ulimit -v " + std::to_string(memory_kib) + " && " : "";
  const std::string cmd = "cd '" + workdir.string() + "' && " + ulimit + limit + "'" + std::string(MILLNET_EXE) + "' " +
                          args + " >'" + out.string() + "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// A fresh, empty folder under the build tree for one test.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::path(MILLNET_BINARY_DIR) / "test_tmp" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// Every file below `dir` (relative names), to prove nothing half-written is left behind.
inline std::string list_files(const std::filesystem::path& dir) {
  std::string s;
  if (!std::filesystem::exists(dir)) return s;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) s += std::filesystem::relative(e.path(), dir).string() + "\n";
  return s;
}

}  // namespace millnet::testing
