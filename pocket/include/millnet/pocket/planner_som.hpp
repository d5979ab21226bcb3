#pragma once
// The SOM planner (Shin & Suh §3–§5): tool points on the stepover grid → SOM tour → weak smoothing,
// 2-opt/Or-opt with obstacle-aware costs → strong smoothing (links through the pocket, else
// retract–rapid–plunge) → chains of straight moves at the cutting level.
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/smoothing.hpp"
#include "millnet/pocket/som.hpp"

namespace millnet::pocket {

/// Plans one level of `region` (validated and normalized: boundary CCW, islands CW; mm).
///   * tool points: make_tool_points(region, frame, cut.clearance()) — frame.spacing is the stepover
///     grid g (the caller usually sets frame.spacing = cut.stepover);
///   * path: chains of straight moves between tool points (bulges 0), feeds 0 (unassigned), role "cut",
///     predrill = true (each chain starts in uncut material); predrill lists every chain's start;
///   * stats: SomStats (the smoothing's figures, the SOM's, the path's lengths, grid_bound_mm = (N − 1)·g).
/// No tool point ⇒ status NoToolPoints with a message, an empty path and no stats (std::monostate). Deterministic for som.seed.
/// Example: `auto r = plan_som(region, cut, GridFrame{{0, 0}, 0, cut.stepover}, {}, {});`
[[nodiscard]] PlanResult plan_som(const Region& region, const CutParams& cut, const GridFrame& frame,
                                  const SomParams& som, const SmoothingParams& smooth);

}  // namespace millnet::pocket
