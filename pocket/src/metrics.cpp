// Metrics: key/value order and the uncut area.
#include "millnet/pocket/metrics.hpp"

#include "millnet/pocket/tolerances.hpp"

#include "offset.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::pocket {

std::vector<std::pair<std::string, double>> Metrics::to_key_values() const {
  std::vector<std::pair<std::string, double>> kv = {{"tool_points", tool_points},
                                                    {"tour_length_mm", tour_length_mm},
                                                    {"cut_length_mm", cut_length_mm},
                                                    {"rapid_length_mm", rapid_length_mm},
                                                    {"retractions", retractions},
                                                    {"plunges", plunges},
                                                    {"predrill_points", predrill_points},
                                                    {"planning_time_s", planning_time_s},
                                                    {"time_adjusted_min", time_adjusted_min},
                                                    {"time_constant_min", time_constant_min},
                                                    {"uncut_area_mm2", uncut_area_mm2},
                                                    {"reachable_area_mm2", reachable_area_mm2},
                                                    {"pocket_area_mm2", pocket_area_mm2},
                                                    {"levels", levels},
                                                    {"time_kinematic_min", time_kinematic_min},
                                                    {"max_engagement_deg", max_engagement_deg}};
  const std::size_t fixed = kv.size();
  for (const auto& stat : key_values(planner_stats)) {  // O(stats · fields)
    const bool taken = std::any_of(kv.begin(), kv.begin() + static_cast<std::ptrdiff_t>(fixed),
                                   [&](const auto& e) { return e.first == stat.first; });
    if (!taken) kv.push_back(stat);
  }
  return kv;
}

UncutArea uncut_area(const Region& region, const Path2D& path, double clearance_mm, double tool_radius_mm) {
  UncutArea u;
  const auto centre_area = offset_inward(region, clearance_mm + tol::contour_margin_mm, tol::uncut_chord_mm);
  const auto reachable = offset_areas(centre_area, tool_radius_mm, tol::uncut_chord_mm);
  u.reachable_mm2 = area(reachable);
  std::vector<std::vector<Vec2>> lines;
  for (const Chain& ch : path.chains)  // O(flattened path vertices)
    if (!ch.pts.empty()) lines.push_back(flatten_open(ch.pts, tol::uncut_chord_mm));
  const auto swept = swept_area(lines, tool_radius_mm, tol::uncut_chord_mm);
  u.uncut = difference(reachable, swept);
  u.uncut_mm2 = area(u.uncut);
  return u;
}

}  // namespace millnet::pocket
