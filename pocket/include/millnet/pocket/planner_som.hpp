#pragma once
// The SOM planner (Shin & Suh §3–§5): tool points on the stepover grid → SOM tour → weak smoothing,
// 2-opt/Or-opt with obstacle-aware costs → strong smoothing (links through the pocket, else
// retract–rapid–plunge) → chains of straight moves at the cutting level.
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_registry.hpp"
#include "millnet/pocket/smoothing.hpp"
#include "millnet/pocket/som.hpp"

#include <string_view>

namespace millnet::pocket {

/// What the planner adds to the seed's tour (issue 11: the SOM planner clears the pocket by itself
/// and keeps the machine's speed). Both off = the seed's planner (configs/presets/shin-suh-1995).
struct SomPathParams {
  /// Wall rings: the region offset inward by clearance + tol::contour_margin_mm (the loops the
  /// contour pass cuts: outer CCW, holes CW, climb with M3), each spliced into the tour with the tool
  /// down where the two moves to and from its start are move_ok and cost least; grid points closer
  /// than s = R − g/√2 to a ring are not tool points (R the tool radius, g the grid spacing; none when
  /// s ≤ 0). The plan then has walls_cut = true: every reachable point within R of a ring is swept
  /// by it, and every other one lies > R inside the rings, so the grid point nearest to it (≤ g/√2
  /// away) is a tool point the tour visits.
  bool walls = true;
  /// Corners of the tour at grid points blended by tangent arcs (blend_corners) whose midpoint lies
  /// at most 0.9·s from the corner (the coverage argument above keeps ≥ 0.1·s to spare), radius at
  /// most blend_radius_mm; ring vertices stay sharp. Straight-on vertices are merged.
  bool blend_corners = true;
  double blend_radius_mm = 0;  ///< 0 ⇒ auto = grid spacing / 2; ≥ 0
};

/// Plans one level of `region` (validated and normalized: boundary CCW, islands CW; mm).
///   * tool points: make_tool_points(region, frame, cut.clearance()) — frame.spacing is the stepover
///     grid g (the caller usually sets frame.spacing = cut.stepover);
///   * path: chains of straight moves between tool points (bulges 0), feeds 0 (unassigned), role "cut",
///     predrill = true (each chain starts in uncut material); predrill lists every chain's start;
///   * stats: SomStats (the smoothing's figures, the SOM's, the path's lengths, grid_bound_mm = (N − 1)·g).
///   * `path` (SomPathParams): with walls, the wall rings spliced in with the tool down and
///     walls_cut = true (a wall ring that no chain reaches with a move_ok move is a chain of its
///     own); with blend_corners, arcs at the tour's corners (chains then have bulges and vertices
///     that are not tool points).
/// With walls, a region whose grid has no tool point but whose rings exist is cut by the rings alone.
/// No tool point ⇒ status NoToolPoints with a message, an empty path and no stats (std::monostate). Deterministic for som.seed.
/// Example: `auto r = plan_som(region, cut, GridFrame{{0, 0}, 0, cut.stepover}, {}, {});`
[[nodiscard]] PlanResult plan_som(const Region& region, const CutParams& cut, const GridFrame& frame,
                                  const SomParams& som, const SmoothingParams& smooth, const SomPathParams& path = {});

/// The SOM planner (grid tool points → self-organising tour → smoothing) and its parameters.
struct SomSpec {
  static constexpr std::string_view kPlanner = "som";
  GridFrame frame;
  SomParams som;
  SmoothingParams smooth;
  SomPathParams path;  ///< wall rings and corner arcs (issue 11)
};

/// The registry's entry (planner_registry.hpp): settings /pocket/grid, /pocket/som, /pocket/smoothing.
[[nodiscard]] PlannerEntry som_planner();

}  // namespace millnet::pocket
