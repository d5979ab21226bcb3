#pragma once
// Drilling cycles (G81 drill, G83 peck drill) as the moves they stand for, the way LinuxCNC's
// interpreter expands them (src/emc/rs274ngc/interp_cycles.cc): the reader expands a cycle block
// into these moves, a job's drilling operation is built from them, and the writer, on a dialect
// with canned cycles, writes a run of moves it recognises as one hole back as one cycle block. One
// function makes the moves, so the three agree exactly.
//
// One hole from the current position `from` (absolute, mm), retract mode G98 (back to the Z the
// tool was at before the cycle, or R if that is lower):
//   1. Z rapid up to R when the tool is below it;      2. X Y rapid to the hole (when not there);
//   3. Z rapid down to R (when not there);             4. G81: feed to the bottom.
//      G83: feed down by Q, rapid up to R, rapid down to kPeckRapidBackMm above that depth, feed on
//      by Q …, the last feed to the bottom (LinuxCNC: depth steps of Q from R while above the bottom);
//   5. Z rapid up to the retract height.
// Every move carries `cycle` (81 or 83) so that the writer can recognise it.
#include "millnet/gcode/program.hpp"

#include <vector>

namespace millnet::gcode {

/// LinuxCNC's G83 rapid back down: 0.010 inch above the depth reached (interp_internal.hh
/// G83_RAPID_DELTA), whatever the program's unit.
inline constexpr double kPeckRapidBackMm = 0.254;

/// One hole of a drilling cycle, mm, absolute.
struct DrillHole {
  double x = 0, y = 0;
  double bottom_z = 0;  ///< Z word: the hole's bottom (≤ r_z)
  double r_z = 0;       ///< R word: the plane the feed starts from
  double peck_mm = 0;   ///< Q word: 0 = G81, > 0 = G83 with this depth per peck
  double feed = 0;      ///< mm/min
};

/// The moves of `hole` from `from` (whose axes `known` are known: an unknown Z is taken to be above
/// R, as a cycle after a tool change at the safe height), retracting to `retract_z` (G98: the Z
/// before the cycle series, at least R). O(depth / Q).
[[nodiscard]] std::vector<Move> drill_cycle_moves(const Point3& from, std::uint8_t known, const DrillHole& hole,
                                                  double retract_z);

}  // namespace millnet::gcode
