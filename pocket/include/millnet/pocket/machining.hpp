#pragma once
// The facade `millnet pocket` calls once a planner has produced its PlanResult:
//   region + cut parameters + plan → contour pass (optional) → feed map → levels → G-code → metrics.
// Example:
//   PlanResult plan = my_planner(region, cut);              // SOM, zigzag, …
//   MachiningResult m = machine_pocket(region, cut, plan, {.entry = Entry::Predrill, .contour = true});
//   if (m.status != PlanStatus::Ok) { report m.message; write no G-code; }
//   else gcode::write_program(out / (stem + ".nc"), m.program, dialect);
#include "millnet/gcode/stats.hpp"
#include "millnet/pocket/feedmap.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/metrics.hpp"
#include "millnet/pocket/planner.hpp"

#include <string>
#include <vector>

namespace millnet::pocket {

struct MachiningOptions {
  Entry entry = Entry::Predrill;
  double entry_angle_deg = 3.0;    ///< helix and ramp descent angle (GcodeParams::entry_angle_deg)
  double ramp_clearance_mm = 0.2;  ///< where a helix or ramp starts above the material (GcodeParams)
  bool contour = false;            ///< final pass along the offset walls of each reachable component
  /// The wall loops join the path with the tool down where a way through cut material reaches one
  /// (link_wall_chains), and so does each of the planner's chains where one reaches its start
  /// (link_chains; not with helix entry holes, whose chains count on their helix): no retraction
  /// (issue 11). false: every loop and chain entered after a retraction (the programs of before,
  /// configs/presets/shin-suh-1995).
  bool link_walls = true;
  std::string program_name;
  std::vector<std::string> comments;  ///< extra header comments (e.g. the source file, planner)
  gcode::MotionModel machine;         ///< for Metrics::time_kinematic_min
};

struct MachiningResult {
  PlanStatus status = PlanStatus::Ok;
  std::string message;
  Path2D path;               ///< one level's path with feeds (area clearing + contour chains)
  FeedProfile feed_profile;  ///< per piece: s, engagement, feed, MRR (first level)
  std::vector<LevelPlan> levels;
  /// machine_levels: per entry of `levels`, the reachable area of its region the level's path
  /// leaves uncut, mm² (uncut_area); the metrics hold their sums.
  std::vector<double> level_uncut_mm2;
  gcode::Program program;  ///< the program (empty when status != Ok); written by gcode::write_program
  Metrics metrics;
};

/// Contour chains along the walls: region offset inward by clearance + tol::contour_margin_mm, one
/// closed chain per loop (outer CCW, holes CW: climb milling with M3), each loop starting at its
/// vertex nearest to the area-clearing path (`after`; no pre-drill needed when that vertex lies
/// within R/2 of it). O(loop vertices · path vertices).
[[nodiscard]] std::vector<Chain> contour_chains(const Region& region, const CutParams& cut, const Path2D& after);

/// Appends the wall loops (contour_chains) to the path with the tool down where it can (issue 11):
/// after each, the loop (of those left) whose start, any of its vertices kWallStartMm apart, a way
/// through cut material reaches with the shortest link (pocket/cut_links.hpp), started there. Where
/// none is reachable, the first loop left joins the chain before it by a straight move from its
/// vertex nearest that chain's end where that move sweeps no wall, or stays a chain of its own.
/// O(loops · (link query + loop vertices)).
void link_wall_chains(const Region& region, const CutParams& cut, Path2D& path, std::vector<Chain>& walls);

/// Joins each chain of `path` to the chain before it with the tool down where a way through cut
/// material reaches its start (pocket/cut_links.hpp: what it cuts outside the area already swept
/// is what that chain's first moves cut anyway): one retraction and one entry fewer each. The
/// joined chains' starts leave `predrill` (no pre-drilled hole needed there now). Returns the number
/// of joins. O(chains · link query).
std::size_t link_chains(const Region& region, const CutParams& cut, Path2D& path, std::vector<Vec2>& predrill);

/// What the operation adds to a planner's path (`plan`'s path and predrill points, given as `path`
/// and `predrill`), the one place machine_pocket and `millnet rough` (per level region) decide it:
/// with opt.contour and a planner without its own wall pass (PlanResult::walls_cut false), the
/// wall pass (contour_chains, joined by link_wall_chains with opt.link_walls, else each a chain of
/// its own); then with opt.link_walls every chain joined to the one before (link_chains), except
/// with helix entry holes, whose chains count on their helix. Chains still entering uncut
/// material are collected per level by the G-code stage (their `predrill` flag).
void complete_path(const Region& region, const CutParams& cut, const PlanResult& plan, const MachiningOptions& opt,
                   Path2D& path, std::vector<Vec2>& predrill);

/// Largest engagement angle of a feed profile (Metrics::max_engagement_deg), degrees.
[[nodiscard]] double max_engagement_deg(const FeedProfile& profile);

/// Runs everything after planning. The region must be validated (validate_and_normalize). Throws
/// millnet::Error on bad parameters; a plan without a path comes back with its status and message.
[[nodiscard]] MachiningResult machine_pocket(const Region& region, const CutParams& cut, const PlanResult& plan,
                                             const MachiningOptions& opt = {});

/// Machines a stack of already planned levels (issue 5: a different region and plan per Z level,
/// top-down; each level's path gets its own feed map). Fills levels, program and the program
/// figures of metrics (not tool_points / tour / planning time / uncut area).
[[nodiscard]] MachiningResult machine_levels(std::vector<LevelPlan> levels, const CutParams& cut,
                                             const MachiningOptions& opt = {});

/// A pocket counts as cleared when at most this much of its reachable area stays uncut (issue 11's
/// goal), mm².
inline constexpr double kClearedUncutMm2 = 2.0;

/// Rank of each result (1 = best) by time to a cleared pocket: results that planned (status Ok)
/// and clear the pocket first, each group by the motion model's time (time_kinematic_min; ties: the
/// order given). O(n log n).
[[nodiscard]] std::vector<std::size_t> rank_by_time_to_clear(const std::vector<const MachiningResult*>& results);

}  // namespace millnet::pocket
