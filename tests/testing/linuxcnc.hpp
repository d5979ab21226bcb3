#pragma once
// LinuxCNC's own interpreter as the judge of the programs millnet writes (`rs274 -g`, from
// linuxcnc-uspace). The interpreter answers 0 for a program it accepts and 1 for one it refuses;
// its own failures (below) are asked again.
#include <cstdio>
#include <cstdlib>
#include <string>

namespace millnet::testing {

/// The exit status of `rs274 [-t tool_table] -g nc_path` (0: accepted). Any other answer is asked
/// again, up to three times: a refusal is the interpreter's verdict on the file and comes back the
/// same, while a death by a signal (135, SIGBUS, once) or a refusal that a second reading of the same
/// bytes accepts (CI once saw a 466,000-line job program refused that it accepts in every other run)
/// is the interpreter's own failure. Each failed reading's status and the last lines of what it
/// said go to stderr.
inline int linuxcnc_status(const std::string& nc_path, const std::string& tool_table = {}) {
  const std::string tools = tool_table.empty() ? std::string() : "-t '" + tool_table + "' ";
  const std::string log = nc_path + ".rs274.log";  // its last lines and its status
  const std::string cmd = "{ /usr/bin/rs274 " + tools + "-g '" + nc_path +
                          "' </dev/null 2>&1; echo \"rs274-status $?\"; } | tail -n 6 >'" + log + "'";
  int code = -1;
  for (int attempt = 0; attempt < 3; ++attempt) {
    code = -1;
    if (std::system(cmd.c_str()) == 0)
      if (std::FILE* f = std::fopen(log.c_str(), "r")) {
        char line[4096];
        while (std::fgets(line, sizeof line, f) != nullptr) std::sscanf(line, "rs274-status %d", &code);
        std::fclose(f);
      }
    if (code == 0) break;
    std::fprintf(stderr, "note: rs274 answered %d on %s (reading %d of 3); its last lines:\n", code, nc_path.c_str(),
                 attempt + 1);
    std::fflush(stderr);
    (void)std::system(("cat '" + log + "' >&2").c_str());
  }
  std::remove(log.c_str());
  return code;
}

/// LinuxCNC's interpreter accepts the program file. With `tool_table` (a LinuxCNC tool.tbl), the
/// tools the program changes to are the table's.
inline bool linuxcnc_accepts(const std::string& nc_path, const std::string& tool_table = {}) {
  return linuxcnc_status(nc_path, tool_table) == 0;
}

}  // namespace millnet::testing
