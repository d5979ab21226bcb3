// plan_som on the three bench pockets (tool Ø10, stepover 5, grid anchored at (0, 0)): the goals of
// issue 3 as assertions, with an independent gouge check on flattened walls.
#include "millnet/pocket/planner_som.hpp"

#include "millnet/pocket/io/pocket_io.hpp"

#include <gtest/gtest.h>

#include <set>

namespace mp = millnet::pocket;

namespace {

mp::Region load_bench_pocket(const std::string& name) {
  return mp::read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json").region;
}

double seg_seg_dist(const mp::Vec2& p, const mp::Vec2& q, const mp::Vec2& a, const mp::Vec2& b) {
  auto pd = [](const mp::Vec2& x, const mp::Vec2& u, const mp::Vec2& v) {
    const mp::Vec2 d = v - u;
    const double l2 = d.squaredNorm();
    const double t = l2 > 0 ? std::clamp((x - u).dot(d) / l2, 0.0, 1.0) : 0.0;
    return (u + t * d - x).norm();
  };
  auto cross = [](const mp::Vec2& u, const mp::Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double d1 = cross(q - p, a - p), d2 = cross(q - p, b - p), d3 = cross(b - a, p - a), d4 = cross(b - a, q - a);
  if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0))) return 0.0;
  return std::min({pd(p, a, b), pd(q, a, b), pd(a, p, q), pd(b, p, q)});
}

/// Smallest distance from any cutting move to any wall (flattened within 0.001 mm). O(moves · wall segments).
double min_wall_distance(const mp::Region& r, const mp::Path2D& path) {
  std::vector<std::vector<mp::Vec2>> walls{mp::flatten(r.boundary, 0.001)};
  for (const auto& isl : r.islands) walls.push_back(mp::flatten(isl, 0.001));
  double best = 1e300;
  for (const auto& ch : path.chains)
    for (std::size_t k = 0; k + 1 < ch.pts.size(); ++k)
      for (const auto& w : walls)
        for (std::size_t s = 0; s < w.size(); ++s)
          best = std::min(best, seg_seg_dist(ch.pts[k].p(), ch.pts[k + 1].p(), w[s], w[(s + 1) % w.size()]));
  return best;
}

}  // namespace

class PlanSomBench : public ::testing::TestWithParam<const char*> {};

TEST_P(PlanSomBench, MeetsTheIssueGoals) {
  const mp::Region region = load_bench_pocket(GetParam());
  mp::CutParams cut;  // Ø10, stepover 5
  const mp::GridFrame frame{{0, 0}, 0, cut.stepover};
  // The seed's planner (issue 3): grid points only, no wall rings, no corner arcs (test_som_walls.cpp
  // has the planner with them).
  const mp::SomPathParams seed{.walls = false, .blend_corners = false};
  const auto r = mp::plan_som(region, cut, frame, {}, {}, seed);
  ASSERT_EQ(r.status, mp::PlanStatus::Ok) << r.message;
  const double n = static_cast<double>(std::get<mp::SomStats>(r.stats).tool_points);
  ASSERT_GT(n, 10);
  // every tool point is cut, inside chains that move only between tool points
  std::set<std::pair<double, double>> visited;
  for (const auto& ch : r.path.chains)
    for (const auto& v : ch.pts) visited.insert({v.x, v.y});
  EXPECT_EQ(visited.size(), r.tool_points.pts.size());
  // goals: retractions = separate reachable regions − 1, no gouge, cut ≤ 1.05·(N − 1)·g
  EXPECT_EQ(r.path.retractions(),
            static_cast<std::size_t>(std::get<mp::SomStats>(r.stats).smoothing.reachable_regions - 1))
      << GetParam();
  EXPECT_EQ(r.predrill.size(), r.path.chains.size());
  EXPECT_GE(min_wall_distance(region, r.path), cut.clearance() - 0.01) << GetParam();
  EXPECT_LE(r.path.cut_length(), 1.05 * (n - 1) * cut.stepover) << GetParam();
  // deterministic
  const auto again = mp::plan_som(region, cut, frame, {}, {}, seed);
  ASSERT_EQ(again.path.chains.size(), r.path.chains.size());
  for (std::size_t k = 0; k < r.path.chains.size(); ++k) {
    ASSERT_EQ(again.path.chains[k].pts.size(), r.path.chains[k].pts.size());
    for (std::size_t m = 0; m < r.path.chains[k].pts.size(); ++m) {
      EXPECT_EQ(again.path.chains[k].pts[m].x, r.path.chains[k].pts[m].x);
      EXPECT_EQ(again.path.chains[k].pts[m].y, r.path.chains[k].pts[m].y);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BenchPockets, PlanSomBench, ::testing::Values("four_islands", "comb", "eight_islands"));

TEST(PlanSom, SeedLikeStrongSmoothingRetractsAndStaysGougeFree) {
  const mp::Region region = load_bench_pocket("four_islands");
  mp::CutParams cut;
  const mp::GridFrame frame{{0, 0}, 0, cut.stepover};
  const auto r = mp::plan_som(region, cut, frame, {}, {.linking = false, .weak = true, .extra_passes = false},
                              {.walls = false, .blend_corners = false});
  ASSERT_EQ(r.status, mp::PlanStatus::Ok);
  // the plain SOM tour crosses islands: without links every crossing is a retraction
  EXPECT_GT(r.path.retractions(), 0U);
  EXPECT_EQ(r.path.retractions(),
            static_cast<std::size_t>(std::get<mp::SomStats>(r.stats).smoothing.retractions_before_linking));
  EXPECT_GE(min_wall_distance(region, r.path), cut.clearance() - 0.01);
}

TEST(PlanSom, NoToolPointIsAStatusNotAnException) {
  mp::Region region;
  region.boundary = {{0, 0, 0}, {8, 0, 0}, {8, 8, 0}, {0, 8, 0}};  // smaller than the Ø10 tool
  mp::validate_and_normalize(region, "test");
  mp::CutParams cut;
  const auto r = mp::plan_som(region, cut, mp::GridFrame{{0, 0}, 0, 5}, {}, {});
  EXPECT_EQ(r.status, mp::PlanStatus::NoToolPoints);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(r.path.chains.empty());
}
