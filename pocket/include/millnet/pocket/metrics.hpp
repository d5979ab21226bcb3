#pragma once
// Figures of one machined pocket (what `millnet pocket` writes to <stem>.metrics.json).
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/planner_stats.hpp"

#include <string>
#include <utility>
#include <vector>

namespace millnet::pocket {

struct Metrics {
  double tool_points = 0;
  double tour_length_mm = 0;   ///< the SOM tour's length (SmoothingStats) or the level path's cut length
  double cut_length_mm = 0;    ///< XY feed length of the whole program (all levels, entries, contour)
  double rapid_length_mm = 0;  ///< XY rapid length of the whole program (incl. pre-drilling)
  double retractions = 0;      ///< milling retractions to safe Z followed by another entry
  double plunges = 0;          ///< milling entries (plunge, helix or ramp)
  double predrill_points = 0;  ///< distinct pre-drilled holes (entry "predrill") / entries needing one
  double planning_time_s = 0;
  double time_adjusted_min = 0;  ///< with the feed-map feeds (rapids at rapid_rate)
  double time_constant_min = 0;  ///< every lateral cut at f₂
  /// The program run through the machine's motion model (gcode::stats: acceleration, junction
  /// deviation, look-ahead), MachiningOptions::machine: what the machine takes.
  double time_kinematic_min = 0;
  /// Largest radial engagement along the first level, from the feed map's cells: the arc of the
  /// tool's circumference in the cut, acos(1 − 2·a_e/D) with a_e = D·n₃/n₁ (full slot = 180°).
  double max_engagement_deg = 0;
  double uncut_area_mm2 = 0;  ///< reachable area − swept area at the floor level (Clipper)
  double reachable_area_mm2 = 0;
  double pocket_area_mm2 = 0;
  double levels = 0;
  PlannerStats planner_stats;  ///< the plan's figures, as they are
  /// Ordered (key, value) pairs: the fields above in this order, then key_values(planner_stats) (a
  /// planner key equal to a field name is skipped: the field wins).
  [[nodiscard]] std::vector<std::pair<std::string, double>> to_key_values() const;
};

/// Area the tool can reach (region offset inward by `clearance_mm` + the planners' wall margin
/// tol::contour_margin_mm, grown back by `tool_radius_mm`) minus the area the disk sweeps along every
/// chain of `path` (Clipper union of capsules, arcs flattened within tol::uncut_chord_mm; area error
/// ≈ perimeter × that chord). mm². (Without the 0.6 µm margin a wall pass that follows the walls
/// exactly left perimeter × 0.0006 mm² "uncut": 4.8 mm² on a 2 × 2 m pocket, over the 2 mm² a
/// cleared pocket may leave; issue 42.)
struct UncutArea {
  double reachable_mm2 = 0, uncut_mm2 = 0;
  std::vector<PolyArea> uncut;
};
[[nodiscard]] UncutArea uncut_area(const Region& region, const Path2D& path, double clearance_mm,
                                   double tool_radius_mm);

}  // namespace millnet::pocket
