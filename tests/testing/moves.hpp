#pragma once
// One motion block as the tests write programs by hand (the axes a block states default to X Y Z).
#include "millnet/gcode/program.hpp"

#include <cstdint>

namespace millnet::testing {

[[nodiscard]] inline gcode::Move move(gcode::Motion m, gcode::Point3 to, double feed = 0,
                                      std::uint8_t axes = gcode::kXYZ, std::uint8_t op = 0) {
  gcode::Move v;
  v.motion = m;
  v.to = to;
  v.feed = feed;
  v.axes = axes;
  v.op = op;
  return v;
}

}  // namespace millnet::testing
