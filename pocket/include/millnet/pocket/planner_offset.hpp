#pragma once
// The offset (contour-parallel) planner: inward offsets of the walls at the stepover, cut from the
// inside out, linked with the tool down.
//
//   rings  A_k = offset_inward(region, clearance + margin + k·stepover), k = 0, 1, … until empty;
//          every loop of every A_k is one ring (outer loops CCW, island loops CW, as Clipper returns
//          them). A_0's loops are the wall pass: the plan clears the walls by itself.
//   tree   a component of A_{k+1} lies in exactly one component of A_k (its parent); where the
//          offsets split, a component has several children.
//   order  per reachable component (a root): enter at the deepest leaf (the helix / ramp / pre-drill
//          entry of pocket/gcode.hpp), cut the rings on the way up to the root, inside out; at each
//          node the children off that way are cut top-down (each ring after the one around it), then
//          the way continues up.
//   links  the next ring starts at its vertex nearest to the tool; the straight move there keeps
//          the tool down when it sweeps no wall (Clearance::move_ok), else the tool retracts and the
//          next chain enters as a cut point (within R/2 of the path so far) or as uncut material.
//
// Coverage: every point of A_k within `stepover` of A_k's boundary is swept by a ring of A_k (when
// stepover ≤ R); every deeper point lies in A_{k+1}. So with stepover ≤ tool radius the rings
// sweep all of A_0 ⊕ R, the reachable area. Above R, ridges may stay (metrics' uncut area says).
//
// Direction: climb milling with M3 (outer loops CCW, island loops CW) or conventional (reversed).
// Cost: K offsets of the whole region (K = inscribed radius / stepover), O(n log n) each, plus
// O(rings · ring vertices) for the nearest starts and O(links · walls nearby) for the link checks.
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_registry.hpp"

#include <string_view>

namespace millnet::pocket {

struct OffsetParams {
  bool climb = true;  ///< climb milling with a clockwise spindle (M3); false: conventional
};

/// The offset (contour-parallel) planner: rings at the stepover, inside out, walls included.
struct OffsetSpec {
  static constexpr std::string_view kPlanner = "offset";
  OffsetParams offset;
};

/// The registry's entry (planner_registry.hpp): settings /pocket/offset.
[[nodiscard]] PlannerEntry offset_planner();

/// Plans `region` (validated and normalized) contour-parallel. PlanResult::planner = "offset",
/// walls_cut = true, stats: OffsetStats. Status NoToolPoints when the tool fits nowhere.
/// Throws millnet::Error as CutParams::check.
[[nodiscard]] PlanResult plan_offset(const Region& region, const CutParams& cut, const OffsetParams& params);

}  // namespace millnet::pocket
