#pragma once
// One planner interface: a planner turns a validated, normalized region and the cut parameters into
// a 2D plan at one level (feeds unassigned). pocket/machining.hpp then adjusts feeds from the feed
// map, repeats the plan at every step-down, writes G-code and metrics.
#include "millnet/pocket/planner_stats.hpp"
#include "millnet/pocket/toolpath.hpp"
#include "millnet/pocket/toolpoints.hpp"

#include <string>
#include <vector>

namespace millnet::pocket {

struct PlanResult {
  PlanStatus status = PlanStatus::Ok;
  std::string message;         ///< why the path is empty when status != Ok
  std::string planner;         ///< "som", "zigzag-t", "zigzag-i", …
  ToolPoints tool_points;      ///< the grid points the path visits (SOM); may be empty
  Path2D path;                 ///< chains in machining order, feeds 0 (unassigned)
  std::vector<Vec2> predrill;  ///< entry points that need a pre-drilled hole
  PlannerStats stats;          ///< the planner's figures (SomStats, ZigzagStats, …)
  /// The path already runs along every wall (the offset planner's first rings): machine_pocket
  /// adds no contour pass.
  bool walls_cut = false;
  /// The plan counts on what a helix entry clears (the adaptive planner): with Entry::Helix,
  /// machine_pocket's feed map marks each helix's disk (entry_helix: radius rh + R) at its chain's
  /// start. Off for the other planners, whose feeds and programs stay as they were.
  bool helix_entry_holes = false;
  double planning_time_s = 0;
};

}  // namespace millnet::pocket
