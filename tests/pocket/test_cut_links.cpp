// Links through cut material (pocket/cut_links.hpp, issue 11), against a brute-force oracle: along
// a returned way, sampled every 0.1 mm, every point of a 0.2 mm grid inside the tool's disk (a
// hair inside it) lies within R of what was swept, of the start, or of the target's approach, or
// in the wall band near the target; and no way is returned where none exists.
#include "millnet/pocket/cut_links.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace millnet::pocket;

namespace {

Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }

CutParams tool10() {
  CutParams cut;
  cut.tool.diameter = 10;
  cut.stepover = 5;
  return cut;
}

double dist_polyline(const std::vector<Vec2>& pl, const Vec2& p) {
  if (pl.size() == 1) return (pl[0] - p).norm();
  double best = 1e300;
  for (std::size_t k = 0; k + 1 < pl.size(); ++k) {
    const Vec2 d = pl[k + 1] - pl[k];
    const double t = std::clamp((p - pl[k]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (pl[k] + t * d)).norm());
  }
  return best;
}

/// Largest stretch of the way's swept disk (shrunk by 0.3 mm: the raster's cell and the exact
/// check's sliver allowance) that lies outside what the rules allow, counted in 0.2 mm grid points.
std::size_t fresh_points(const std::vector<Vec2>& way, const std::vector<std::vector<Vec2>>& swept, const LinkTarget& t,
                         const Region& region, double R, double band) {
  const Clearance walls(region, 0.0);
  std::size_t bad = 0;
  const double r = R - 0.3;
  for (std::size_t k = 0; k + 1 < way.size(); ++k) {
    const int n = std::max(1, static_cast<int>(std::ceil((way[k + 1] - way[k]).norm() / 0.1)));
    for (int i = 0; i <= n; ++i) {
      const Vec2 p = way[k] + (way[k + 1] - way[k]) * (static_cast<double>(i) / n);
      for (double dy = -r; dy <= r; dy += 0.2)
        for (double dx = -r; dx <= r; dx += 0.2) {
          const Vec2 q = p + Vec2(dx, dy);
          if (Vec2(dx, dy).norm() > r || !inside(region, q)) continue;
          bool ok = (q - way.front()).norm() <= R || dist_polyline(t.approach, q) <= R;
          for (const auto& s : swept) ok = ok || dist_polyline(s, q) <= R;
          ok = ok || ((q - t.b).norm() <= band && walls.wall_distance(q) <= 2 * R);
          bad += ok ? 0 : 1;
        }
    }
  }
  return bad;
}

TEST(CutLinks, WayGoesRoundUncutMaterialThroughTheCutU) {
  // A U cut into a 100 × 60 pocket: down the left arm, along the bottom, up the right arm. The
  // straight move between the arms' tops would cut the uncut middle; the way goes round the U.
  const Region region{rect(0, 0, 100, 60), {}};
  const CutParams cut = tool10();
  CutLinker linker(region, cut, kLinkSliverMm2);
  const std::vector<Vec2> u{{10, 50}, {10, 10}, {90, 10}, {90, 50}};
  linker.sweep(u);
  const LinkTarget t{Vec2(10, 50), {Vec2(10, 50)}, 0.0};
  const auto l = linker.best_link(Vec2(90, 50), {t});
  ASSERT_TRUE(l.has_value());
  EXPECT_EQ(l->target, 0u);
  ASSERT_GE(l->way.size(), 3u) << "the straight move crosses 60 mm of uncut material";
  EXPECT_EQ(l->way.front(), Vec2(90, 50));
  EXPECT_EQ(l->way.back(), Vec2(10, 50));
  double len = 0;
  double lowest = 1e9;
  for (std::size_t k = 0; k + 1 < l->way.size(); ++k) len += (l->way[k + 1] - l->way[k]).norm();
  for (const Vec2& p : l->way) lowest = std::min(lowest, p.y());
  EXPECT_LT(lowest, 16.0) << "it must pass through the bottom of the U";
  EXPECT_GT(len, 80 + 2 * 30.0);  // round the U, at least (80 across, 2 × ≥ 30 down and up: the arms are 10 wide)
  EXPECT_LT(len, 160.0);          // and pulled taut: shorter than the U itself
  EXPECT_EQ(fresh_points(l->way, {u}, t, region, cut.tool.diameter / 2, cut.tool.diameter * 1.5), 0u);
  // Every move keeps the tool's clearance from the walls.
  const Clearance clear(region, cut.clearance() - 0.01);
  for (std::size_t k = 0; k + 1 < l->way.size(); ++k) EXPECT_TRUE(clear.move_ok(l->way[k], l->way[k + 1])) << k;
}

TEST(CutLinks, NoWayThroughUncutMaterialAndTheCheapestTargetWins) {
  const Region region{rect(0, 0, 100, 60), {}};
  const CutParams cut = tool10();
  CutLinker linker(region, cut, kLinkSliverMm2);
  // Two separate cuts: a pass along the bottom, one along the top; nothing joins them.
  linker.sweep(std::vector<Vec2>{{10, 10}, {90, 10}});
  linker.sweep(std::vector<Vec2>{{10, 50}, {90, 50}});
  const LinkTarget top{Vec2(50, 50), {Vec2(50, 50)}, 0.0};
  EXPECT_FALSE(linker.best_link(Vec2(10, 10), {top}).has_value());
  // Along the bottom pass both targets are reachable; the nearer wins, and an extra cost moves it.
  const LinkTarget near{Vec2(30, 10), {Vec2(30, 10)}, 0.0}, far{Vec2(80, 10), {Vec2(80, 10)}, 0.0};
  auto l = linker.best_link(Vec2(10, 10), {top, far, near});
  ASSERT_TRUE(l.has_value());
  EXPECT_EQ(l->target, 2u);
  EXPECT_EQ(l->way.size(), 2u) << "a straight move along the pass";
  LinkTarget costly = near;
  costly.extra = 100;
  l = linker.best_link(Vec2(10, 10), {top, far, costly});
  ASSERT_TRUE(l.has_value());
  EXPECT_EQ(l->target, 1u);
}

TEST(CutLinks, LastMoveMayCutTheTargetsApproachAndTheWallCornerBesideIt) {
  // A pass at y = 15 along a 100 × 60 pocket; the next chain starts in the corner (5, 5) and runs
  // along the bottom wall. The move down from (5, 15) cuts the corner below the pass: what the
  // next chain's first pass and the contour pass cut anyway.
  const Region region{rect(0, 0, 100, 60), {}};
  const CutParams cut = tool10();
  CutLinker linker(region, cut, kLinkSliverMm2);
  const std::vector<Vec2> pass{{95, 15}, {5, 15}};
  linker.sweep(pass);
  const std::vector<Vec2> next{{5, 5}, {95, 5}};
  const LinkTarget t{next.front(), approach_of(next, cut.tool.diameter), 0.0};
  ASSERT_EQ(t.approach.size(), 2u);
  EXPECT_NEAR((t.approach[1] - t.approach[0]).norm(), kApproachDiameters * cut.tool.diameter, 1e-12);
  const auto l = linker.best_link(Vec2(5, 15), {t});
  ASSERT_TRUE(l.has_value());
  EXPECT_EQ(l->way.size(), 2u);
  EXPECT_EQ(fresh_points(l->way, {pass}, t, region, cut.tool.diameter / 2, cut.tool.diameter * 1.5), 0u);
  // Along the bottom wall the band beside a target is allowed too (the contour pass cuts it)...
  const LinkTarget wall{Vec2(60, 5), {Vec2(60, 5)}, 0.0};
  const auto w = linker.best_link(Vec2(5, 15), {wall});
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(fresh_points(w->way, {pass}, wall, region, cut.tool.diameter / 2, cut.tool.diameter * 1.5), 0u);
  // ...but a start in the middle, a stepover beyond the pass, would cut a new band between the two:
  // no way, even with the chain's own first pass as its approach.
  const std::vector<Vec2> inner{{50, 25}, {90, 25}};
  EXPECT_FALSE(
      linker.best_link(Vec2(5, 15), {{inner.front(), approach_of(inner, cut.tool.diameter), 0.0}}).has_value());
}

TEST(CutLinks, IslandInTheWayIsWalkedRound) {
  // A ring cut round a square island; the link from one side to the other follows the ring and
  // keeps the clearance from the island.
  const Region region{rect(0, 0, 100, 100), {{{40, 40, 0}, {40, 60, 0}, {60, 60, 0}, {60, 40, 0}}}};
  const CutParams cut = tool10();
  CutLinker linker(region, cut, kLinkSliverMm2);
  const std::vector<Vec2> ring{{30, 30}, {70, 30}, {70, 70}, {30, 70}, {30, 30}};
  linker.sweep(ring);
  const LinkTarget t{Vec2(70, 70), {Vec2(70, 70)}, 0.0};
  const auto l = linker.best_link(Vec2(30, 30), {t});
  ASSERT_TRUE(l.has_value());
  const Clearance clear(region, cut.clearance() - 0.01);
  for (std::size_t k = 0; k + 1 < l->way.size(); ++k) EXPECT_TRUE(clear.move_ok(l->way[k], l->way[k + 1])) << k;
  EXPECT_EQ(fresh_points(l->way, {ring}, t, region, cut.tool.diameter / 2, cut.tool.diameter * 1.5), 0u);
}

}  // namespace
