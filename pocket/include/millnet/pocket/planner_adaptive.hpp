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
//   passes  the tool advances in steps of step_mm; each step's direction is searched (bisection
//           over the turn angle, material kept on the right for climb milling) so that the newly
//           cut area of the step is the largest one ≤ safety · a_e(target) · step. Where material
//           is narrow this turns into curved / trochoidal moves by itself. A pass ends when every
//           direction is blocked (walls, too much material) or the tool has cut nothing for a
//           while (the idle tail is dropped).
//   links   the next pass starts at the nearest tool position (Dijkstra over a 1 mm lattice of
//           positions whose disk is fully cleared) with uncut material within reach; the tool goes
//           there with its tool down along moves that sweep no wall and cut at most the target
//           (pulled taut); only where no such way exists does it retract (then a new entry).
//   end     when no reachable position sees uncut material of the clearing's target area (the
//           cells the tool can reach from A_0); machine_pocket's contour pass (walls_cut = false)
//           then trims what the raster left along the walls.
//   output  each chain's step points simplified within tol::adaptive_simplify_mm (Douglas–Peucker,
//           every kept chord checked against the walls).
//
// The feed map sees the helix's disk only when PlanResult::helix_entry_holes is set (this planner
// sets it): with another entry the first step out of a plunge is a full slot (180°).
// Deterministic: no threads, no clocks in the decisions.
#include "millnet/pocket/planner.hpp"

namespace millnet::pocket {

struct AdaptiveParams {
  /// Largest radial engagement, degrees in (0, 180]; 0 ⇒ acos(1 − stepover/R) (stepover 5 on a
  /// Ø10 tool ⇒ 90°).
  double max_engagement_deg = 0;
  bool climb = true;        ///< climb milling with M3 (material on the right); false: conventional
  double step_mm = 0;       ///< planning step, 0 ⇒ D/40
  double raster_mm = 0;     ///< cleared-area raster cell, 0 ⇒ D/40
  /// Each step aims at this fraction of the target's newly cut area (raster noise of the
  /// planner's and the feed map's counts), in (0, 1].
  double safety = 0.85;
};

/// The target angle AdaptiveParams ask for (max_engagement_deg, or the stepover's), degrees.
/// Throws millnet::Error when it is outside (0, 180].
[[nodiscard]] double adaptive_target_deg(const CutParams& cut, const AdaptiveParams& params);

/// Plans `region` (validated and normalized) at constant engagement. PlanResult::planner =
/// "adaptive", walls_cut = false (machine_pocket adds the contour pass), helix_entry_holes = true,
/// stats: AdaptiveStats. Status NoToolPoints when the tool fits nowhere. Throws millnet::Error as
/// CutParams::check and on bad AdaptiveParams.
[[nodiscard]] PlanResult plan_adaptive(const Region& region, const CutParams& cut, const AdaptiveParams& params);

}  // namespace millnet::pocket
