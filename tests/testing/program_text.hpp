#pragma once
// The LinuxCNC text of a program (what the tests' independent replays and rs274 read): planners
// return gcode::Program values and the commands write them at the edge (issue 36).
#include "millnet/gcode/writer.hpp"

#include <string>

namespace millnet::testing {

[[nodiscard]] inline std::string linuxcnc_text(const gcode::Program& program) {
  return gcode::write(program, gcode::linuxcnc());
}

}  // namespace millnet::testing
