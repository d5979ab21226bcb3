#include "millnet/pocket/planner_stats.hpp"

#include <algorithm>

namespace millnet::pocket {

std::vector<std::pair<std::string, double>> SomStats::key_values() const {
  std::vector<std::pair<std::string, double>> kv = {{"corner_arcs", static_cast<double>(corner_arcs)},
                                                    {"cut_length_mm", cut_length_mm},
                                                    {"cut_over_bound", cut_over_bound},
                                                    {"grid_bound_mm", grid_bound_mm},
                                                    {"predrill_points", static_cast<double>(predrill_points)},
                                                    {"rapid_length_mm", rapid_length_mm},
                                                    {"retractions", static_cast<double>(retractions)},
                                                    {"som_converged", som_converged ? 1.0 : 0.0},
                                                    {"som_nodes", static_cast<double>(som_nodes)},
                                                    {"som_passes", som_passes},
                                                    {"tool_points", static_cast<double>(tool_points)},
                                                    {"wall_ring_links", static_cast<double>(wall_ring_links)},
                                                    {"wall_rings", static_cast<double>(wall_rings)}};
  const std::size_t own = kv.size();
  for (auto& stat : smoothing.key_values()) {  // O(keys²), a few dozen
    const bool taken = std::any_of(kv.begin(), kv.begin() + static_cast<std::ptrdiff_t>(own),
                                   [&](const auto& e) { return e.first == stat.first; });
    if (!taken) kv.push_back(std::move(stat));
  }
  std::sort(kv.begin(), kv.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return kv;
}

std::vector<std::pair<std::string, double>> ZigzagStats::key_values() const {
  return {{"angle_deg", angle_deg},
          {"angles_tried", static_cast<double>(angles_tried)},
          {"components", components},
          {"contours", 0.0},
          {"faces", static_cast<double>(faces)},
          {"formula_regions", formula_regions},
          {"islands", islands},
          {"nls", nls},
          {"nonmonotone_faces", nonmonotone_faces},
          {"passes", static_cast<double>(passes)},
          {"region_links", static_cast<double>(region_links)},
          {"regions", regions},
          {"srps", static_cast<double>(srps)},
          {"zigzag_cut_length_mm", zigzag_cut_length_mm},
          {"zigzag_rapid_length_mm", zigzag_rapid_length_mm}};
}

std::vector<std::pair<std::string, double>> OffsetStats::key_values() const {
  return {{"arcs", static_cast<double>(arcs)},
          {"components", static_cast<double>(components)},
          {"links", static_cast<double>(links)},
          {"nodes", static_cast<double>(nodes)},
          {"offset_cut_length_mm", cut_length_mm},
          {"offset_rapid_length_mm", rapid_length_mm},
          {"offset_retractions", static_cast<double>(retractions)},
          {"offsets", static_cast<double>(offsets)},
          {"rings", static_cast<double>(rings)},
          {"splits", static_cast<double>(splits)}};
}

std::vector<std::pair<std::string, double>> AdaptiveStats::key_values() const {
  return {{"adaptive_cut_length_mm", cut_length_mm},
          {"adaptive_rapid_length_mm", rapid_length_mm},
          {"adaptive_retractions", static_cast<double>(retractions)},
          {"adaptive_ride_length_mm", ride_length_mm},
          {"adaptive_link_length_mm", link_length_mm},
          {"adaptive_backtrack_length_mm", backtrack_length_mm},
          {"components", static_cast<double>(components)},
          {"entries", static_cast<double>(entries)},
          {"entries_without_helix", static_cast<double>(entries_without_helix)},
          {"links", static_cast<double>(links)},
          {"passes", static_cast<double>(passes)},
          {"idle_passes", static_cast<double>(idle_passes)},
          {"reentries", static_cast<double>(reentries)},
          {"steps", static_cast<double>(steps)},
          {"target_deg", target_deg},
          {"uncut_target_mm2", uncut_target_mm2},
          {"vertices", static_cast<double>(vertices)},
          {"wall_retractions", static_cast<double>(wall_retractions)}};
}

std::vector<std::pair<std::string, double>> key_values(const PlannerStats& stats) {
  return std::visit(
      [](const auto& s) -> std::vector<std::pair<std::string, double>> {
        if constexpr (std::is_same_v<std::decay_t<decltype(s)>, std::monostate>)
          return {};
        else
          return s.key_values();
      },
      stats);
}

}  // namespace millnet::pocket
