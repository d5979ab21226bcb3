#pragma once
// What planning and machining one pocket region will cost, from its size and the resolutions, before
// anything is allocated (issue 12 §1; core/budget.hpp). Counts are exact or stated upper bounds:
//  * SOM: the tool-point grid make_tool_points visits, rows × columns of grid_range() (exact; the
//    tool points are a subset), 24 bytes per grid point (a point and its indices); then its ring,
//    M = max(3, round(node_factor · grid points)) nodes (an upper bound: M = node_factor · tool
//    points), 32 bytes per node.
//  * zigzag: scan lines = (box diagonal / stepover + 1) per direction tried (one with a fixed angle,
//    else ⌈180 / angle_step⌉ + one per boundary segment), 64 bytes per line — an upper bound.
//  * feed map (every planner, machine_pocket): cells of the boundary's box grown by R + g on each
//    side at feed_grid g (exact, as assign_feeds sizes it), 1 byte per cell.
#include "millnet/core/budget.hpp"
#include "millnet/pocket/plan.hpp"

#include <vector>

namespace millnet::pocket {

/// The estimates of one region (validated, normalized) planned with `spec` and machined with `cut`:
/// first the planner's (tool points and ring nodes, or scan lines), then the feed map's.
[[nodiscard]] std::vector<WorkEstimate> estimate_work(const Region& region, const CutParams& cut,
                                                      const PlannerSpec& spec);

/// Throws millnet::Error (the one-line refusal of core/budget.hpp) when an estimate exceeds `limits`.
void check_work(const Region& region, const CutParams& cut, const PlannerSpec& spec, const WorkLimits& limits);

}  // namespace millnet::pocket
