#pragma once
// The adaptive (constant-engagement) planner: a path whose radial engagement stays at or below a
// target angle everywhere, judged by the feed map's model (pocket/feedmap.hpp: newly cut area per
// unit of path = engaged width a_e, angle = acos(1 − a_e/R)).
//
//   raster  the cleared area on a raster of cells (CutParams/AdaptiveParams::raster_mm); material =
//           cells whose centre lies in the region, as in the feed map.
//   centres the tool centre stays in A_0 = region offset inward by clearance + tol::contour_margin_mm
//           (the contour pass's own offset), every move checked exactly (Clearance::move_ok).
//   entry   per reachable component, at the point farthest from the walls; the helix machine_pocket
//           makes there (entry_helix) clears a disk of radius rh + R, which the raster starts with.
//   passes  the tool advances in steps of step_mm. It senses the material as the centroid of the
//           uncut target cells within R + 3 mm (so it finds the material again after a turn) and
//           takes, of the directions from "along the material's edge" (material on the right for
//           climb) to "straight at it", the one turned furthest toward the material whose newly
//           cut area is ≤ safety · a_e(target) · step (bisection). In open material that rides the
//           cut boundary at the target: rings spiralling out from the helix. Moves the walls
//           refuse cost +inf, so a pass slides along a wall; a turn toward the material is limited
//           to 12° a step, so where the material is narrow the pass curls (trochoid-like loops).
//           A pass ends when it could only back away (blocked by a wall and the material ahead),
//           when no target material is in range, or after R + 3 mm that cut nothing (dropped).
//   fronts  a pass that ended blocked is followed by a ride back along the front it was cutting
//           (material on the other side, nothing cut, tool down) to where the front meets a wall,
//           and a new pass from there: climb milling kept, the front cleared from its far end.
//   links   otherwise the next pass starts at the nearest tool position (Dijkstra over a 1 mm
//           lattice of positions whose disk is fully cleared) with uncut material within reach;
//           the tool goes there with its tool down along moves that sweep no wall and cut at most
//           the target (pulled taut); where no way leaves the tool's position it first backtracks
//           along its own path; only where none exists does it retract (then a new entry).
//   end     when no reachable position sees uncut material of the clearing's target area (the
//           cells within R − h/2 of A_0); then the wall pass: every loop of A_0 from its vertex
//           nearest the tool that a link reaches, which trims what the raster left along the
//           walls (walls_cut = true: machine_pocket adds no contour pass).
//   output  each chain's step points simplified within tol::adaptive_simplify_mm (Douglas–Peucker,
//           every kept chord checked against the walls).
//
// The feed map sees the helix's disk only when PlanResult::helix_entry_holes is set (this planner
// sets it): with another entry the first step out of a plunge is a full slot (180°).
// Deterministic: no threads, no clocks in the decisions.
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_registry.hpp"

#include <string_view>

namespace millnet::pocket {

struct AdaptiveParams {
  /// Largest radial engagement, degrees in (0, 180]; 0 ⇒ acos(1 − stepover/R) (stepover 5 on a
  /// Ø10 tool ⇒ 90°).
  double max_engagement_deg = 0;
  bool climb = true;  ///< climb milling with M3 (material on the right); false: conventional
  /// Both ways: a pass that a wall stops turns round and cuts the front's next stripe back in the
  /// other direction instead of riding back to cut it in `climb`'s (helix and walls keep `climb`).
  bool both_ways = false;
  double step_mm = 0;    ///< planning step, 0 ⇒ D/40
  double raster_mm = 0;  ///< cleared-area raster cell, 0 ⇒ D/80 (D/40 past 10⁷ cells)
  /// Each step aims at this fraction of the target's newly cut area (raster noise of the
  /// planner's and the feed map's counts), in (0, 1].
  double safety = 0.9;
};

/// The adaptive (constant-engagement) planner: passes that keep the engagement at a target angle.
struct AdaptiveSpec {
  static constexpr std::string_view kPlanner = "adaptive";
  AdaptiveParams adaptive;
};

/// The registry's entry (planner_registry.hpp): settings /pocket/adaptive.
[[nodiscard]] PlannerEntry adaptive_planner();

/// The target angle AdaptiveParams ask for (max_engagement_deg, or the stepover's), degrees.
/// Throws millnet::Error when it is outside (0, 180].
[[nodiscard]] double adaptive_target_deg(const CutParams& cut, const AdaptiveParams& params);

/// The cleared-area raster's cell, mm: AdaptiveParams::raster_mm, or when it is 0, D/80 — D/40 where
/// the D/80 raster over the region's box grown by D would pass 10⁷ cells.
[[nodiscard]] double adaptive_raster_mm(const Region& region, const CutParams& cut, const AdaptiveParams& params);

/// Plans `region` (validated and normalized) at constant engagement. PlanResult::planner =
/// "adaptive", walls_cut = true (its own wall pass), helix_entry_holes = true,
/// stats: AdaptiveStats. Status NoToolPoints when the tool fits nowhere. Throws millnet::Error as
/// CutParams::check and on bad AdaptiveParams.
[[nodiscard]] PlanResult plan_adaptive(const Region& region, const CutParams& cut, const AdaptiveParams& params);

}  // namespace millnet::pocket
