#pragma once
// LinuxCNC's own interpreter as the judge of the programs millnet writes (`rs274 -g`, from
// linuxcnc-uspace). The interpreter answers 0 for a program it accepts and 1 for one it refuses; a
// death by a signal (the shell's status 128 + n: CI once saw 135, SIGBUS, on a program it accepts
// in every other run) is the interpreter's own failure, not a verdict on the program, and is asked
// again, up to three times, before it is reported as it came.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <sys/wait.h>

namespace millnet::testing {

/// The exit status of `rs274 [-t tool_table] -g nc_path` (0: accepted), with signal deaths retried.
inline int linuxcnc_status(const std::string& nc_path, const std::string& tool_table = {}) {
  const std::string tools = tool_table.empty() ? std::string() : "-t '" + tool_table + "' ";
  const std::string cmd = "/usr/bin/rs274 " + tools + "-g '" + nc_path + "' </dev/null >/dev/null 2>&1";
  int code = -1;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int raw = std::system(cmd.c_str());
    code = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    if (code < 128) return code;
    std::fprintf(stderr, "note: rs274 died (status %d) on %s; asked again\n", code, nc_path.c_str());
  }
  return code;
}

/// LinuxCNC's interpreter accepts the program file. With `tool_table` (a LinuxCNC tool.tbl), the
/// tools the program changes to are the table's.
inline bool linuxcnc_accepts(const std::string& nc_path, const std::string& tool_table = {}) {
  return linuxcnc_status(nc_path, tool_table) == 0;
}

}  // namespace millnet::testing
