#include "millnet/gcode/cycles.hpp"

#include <algorithm>

namespace millnet::gcode {

std::vector<Move> drill_cycle_moves(const Point3& from, std::uint8_t known, const DrillHole& hole, double retract_z) {
  const std::uint8_t cycle = hole.peck_mm > 0 ? 83 : 81;
  std::vector<Move> out;
  Point3 at = from;
  auto go = [&](Motion motion, std::uint8_t axes_stated, double x, double y, double z) {
    Move m;
    m.motion = motion;
    at = {x, y, z};
    m.to = at;
    known = static_cast<std::uint8_t>(known | axes_stated);
    m.axes = known;
    m.feed = motion == Motion::Rapid ? 0 : hole.feed;
    m.cycle = cycle;
    out.push_back(m);
  };
  const bool z_known = (known & kZ) != 0;
  if (z_known && at[2] < hole.r_z) go(Motion::Rapid, kZ, at[0], at[1], hole.r_z);
  if ((known & (kX | kY)) != (kX | kY) || at[0] != hole.x || at[1] != hole.y)
    go(Motion::Rapid, kX | kY, hole.x, hole.y, at[2]);
  if (!z_known || at[2] != hole.r_z) go(Motion::Rapid, kZ, hole.x, hole.y, hole.r_z);
  if (hole.peck_mm > 0) {
    for (double depth = hole.r_z - hole.peck_mm; depth > hole.bottom_z; depth -= hole.peck_mm) {  // O(depth / Q)
      go(Motion::Line, kZ, hole.x, hole.y, depth);
      go(Motion::Rapid, kZ, hole.x, hole.y, hole.r_z);
      go(Motion::Rapid, kZ, hole.x, hole.y, depth + kPeckRapidBackMm);
    }
  }
  go(Motion::Line, kZ, hole.x, hole.y, hole.bottom_z);
  go(Motion::Rapid, kZ, hole.x, hole.y, std::max(retract_z, hole.r_z));
  return out;
}

}  // namespace millnet::gcode
