// Typed planner figures: the keys the metrics files carry, their order, and which value wins.
#include "millnet/pocket/metrics.hpp"
#include "millnet/pocket/planner_stats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

using namespace millnet::pocket;

namespace {
std::vector<std::string> keys(const std::vector<std::pair<std::string, double>>& kv) {
  std::vector<std::string> k;
  for (const auto& e : kv) k.push_back(e.first);
  return k;
}
double value(const std::vector<std::pair<std::string, double>>& kv, const std::string& key) {
  const auto it = std::find_if(kv.begin(), kv.end(), [&](const auto& e) { return e.first == key; });
  EXPECT_NE(it, kv.end()) << key;
  return it == kv.end() ? -1 : it->second;
}
}  // namespace

TEST(PlannerStats, SmoothingKeysSortedAndValuesFromTheirFields) {
  SmoothingStats s;
  s.weak.type1 = 2;
  s.weak.type3 = 1;
  s.weak.saved_mm = 4.5;
  s.opt_moves = 17;
  s.retractions = 3;
  const auto kv = s.key_values();
  const auto k = keys(kv);
  EXPECT_TRUE(std::is_sorted(k.begin(), k.end()));
  EXPECT_EQ(std::adjacent_find(k.begin(), k.end()), k.end());
  EXPECT_EQ(kv.size(), 17u);
  EXPECT_EQ(value(kv, "weak_patterns"), 3.0);
  EXPECT_EQ(value(kv, "weak_type1"), 2.0);
  EXPECT_EQ(value(kv, "weak_type3"), 1.0);
  EXPECT_EQ(value(kv, "weak_smoothing_saved_mm"), 4.5);
  EXPECT_EQ(value(kv, "opt_moves"), 17.0);
  EXPECT_EQ(value(kv, "retractions"), 3.0);
}

TEST(PlannerStats, SomOwnFiguresWinOverTheSmoothingsAndStaySorted) {
  SomStats s;
  s.smoothing.retractions = 5;  // before the path was built
  s.smoothing.rapid_length_mm = 40;
  s.retractions = 2;  // of the path: this one is the planner's figure
  s.rapid_length_mm = 25;
  s.som_converged = true;
  s.smoothing.links = 4;
  const auto kv = s.key_values();
  const auto k = keys(kv);
  EXPECT_TRUE(std::is_sorted(k.begin(), k.end()));
  EXPECT_EQ(std::adjacent_find(k.begin(), k.end()), k.end());
  EXPECT_EQ(kv.size(), 28u);  // 13 own (corner_arcs, wall_rings, wall_ring_links: issue 11) + 17 smoothing − 2 shared
  EXPECT_EQ(value(kv, "retractions"), 2.0);
  EXPECT_EQ(value(kv, "rapid_length_mm"), 25.0);
  EXPECT_EQ(value(kv, "som_converged"), 1.0);
  EXPECT_EQ(value(kv, "links"), 4.0);
}

TEST(PlannerStats, ZigzagKeysSortedWithTheContoursKey) {
  ZigzagStats z;
  z.passes = 11;
  z.angle_deg = 37.5;
  const auto kv = z.key_values();
  const auto k = keys(kv);
  EXPECT_TRUE(std::is_sorted(k.begin(), k.end()));
  EXPECT_EQ(kv.size(), 15u);
  EXPECT_EQ(value(kv, "region_links"), 0.0);
  EXPECT_EQ(value(kv, "contours"), 0.0);
  EXPECT_EQ(value(kv, "passes"), 11.0);
  EXPECT_EQ(value(kv, "angle_deg"), 37.5);
  EXPECT_TRUE(key_values(PlannerStats{}).empty());
}

TEST(PlannerStats, MetricsListTheFieldsThenThePlannersOtherKeys) {
  // The metrics files' keys for a SOM plan: the 14 fields, then the SOM figures whose names are
  // not a field's (tool_points, tour_length_mm, cut/rapid length, retractions, predrill_points).
  Metrics m;
  m.tool_points = 7;
  SomStats s;
  s.tool_points = 99;
  s.grid_bound_mm = 12.5;
  m.planner_stats = s;
  const auto kv = m.to_key_values();
  const std::vector<std::string> expect = {"tool_points",
                                           "tour_length_mm",
                                           "cut_length_mm",
                                           "rapid_length_mm",
                                           "retractions",
                                           "plunges",
                                           "predrill_points",
                                           "planning_time_s",
                                           "time_adjusted_min",
                                           "time_constant_min",
                                           "uncut_area_mm2",
                                           "reachable_area_mm2",
                                           "pocket_area_mm2",
                                           "levels",
                                           "time_kinematic_min",
                                           "max_engagement_deg",
                                           "corner_arcs",
                                           "cut_over_bound",
                                           "grid_bound_mm",
                                           "link_length_mm",
                                           "links",
                                           "min_retractions",
                                           "opt_moves",
                                           "reachable_regions",
                                           "retractions_before_linking",
                                           "som_converged",
                                           "som_nodes",
                                           "som_overcut_moves",
                                           "som_passes",
                                           "som_tour_length_mm",
                                           "two_opt_saved_mm",
                                           "wall_ring_links",
                                           "wall_rings",
                                           "weak_patterns",
                                           "weak_smoothing_saved_mm",
                                           "weak_type1",
                                           "weak_type2",
                                           "weak_type3"};
  EXPECT_EQ(keys(kv), expect);
  EXPECT_EQ(value(kv, "tool_points"), 7.0);  // the field wins
  EXPECT_EQ(value(kv, "grid_bound_mm"), 12.5);
}
