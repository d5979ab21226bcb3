// Direction search of the zigzag planner: fewest regions, then shortest path (ties: fewer passes).
#include "millnet/pocket/planner_zigzag.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace millnet::pocket;

namespace {
CutParams tool10() {
  CutParams c;
  c.tool.diameter = 10;
  c.stepover = 5;
  return c;
}
Region rotated(const Region& r, double deg) {
  Region out = r;
  auto rot = [&](Vertex& v) {
    const Vec2 p = from_scan_frame(Vec2(v.x, v.y), deg);
    v.x = p.x();
    v.y = p.y();
  };
  for (Vertex& v : out.boundary) rot(v);
  for (Loop& l : out.islands)
    for (Vertex& v : l) rot(v);
  return out;
}
double angle_diff(double a, double b) {  // directions mod 180
  const double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180.0 - d);
}
}  // namespace

TEST(DirectionSearch, CandidatesIncludeEdgeDirections) {
  const Region r = rotated(Region{{{0, 0, 0}, {200, 0, 0}, {200, 20, 0}, {0, 20, 0}}, {}}, 33);
  const auto a = candidate_angles(r, 5);
  EXPECT_EQ(a.size(), 36u + 2u);  // 0, 5, …, 175 plus 33° and 123°
  EXPECT_TRUE(std::any_of(a.begin(), a.end(), [](double t) { return std::abs(t - 33) < 1e-9; }));
  EXPECT_TRUE(std::any_of(a.begin(), a.end(), [](double t) { return std::abs(t - 123) < 1e-9; }));
}

TEST(DirectionSearch, LongThinPocketAlongItsLength) {
  // 200 × 20 rotated by 33°: one region at every angle. The idealised zigzag is as long along
  // (3 passes + 2 joins = 580 mm) as across (39 passes + 38 joins = 580 mm); slanted directions are
  // a few % shorter (short end passes) but turn 10× as often: with the turn penalty (one stepover
  // per pass) along the length wins ⇒ 33°, 3 passes.
  const Region r = rotated(Region{{{0, 0, 0}, {200, 0, 0}, {200, 20, 0}, {0, 20, 0}}, {}}, 33);
  ZigzagParams zp;
  zp.angle_deg = std::nullopt;
  std::vector<AngleScore> scores;
  const PlanResult p = plan_zigzag(r, tool10(), zp, &scores);
  ASSERT_EQ(p.status, PlanStatus::Ok);
  const ZigzagStats& st = std::get<ZigzagStats>(p.stats);
  EXPECT_NEAR(st.angle_deg, 33.0, 1e-9);
  EXPECT_EQ(st.regions, 1);
  EXPECT_EQ(st.passes, 3U);
  for (const auto& s : scores) {
    EXPECT_EQ(s.regions, 1) << s.angle_deg;
    if (HasFailure()) std::printf("%g: %d regions %.3f mm\n", s.angle_deg, s.regions, s.length_mm);
  }
}

TEST(DirectionSearch, LShapedPocketFewestRegionsThenLongestEdge) {
  // L: a 150 × 30 foot and a 30 × 50 upright, rotated by 20°. Regions: 1 when the passes run within
  // [20°, 110°] (the reflex corner is not a scan extremum), 2 otherwise (it is one: an SRP).
  // Best: parallel to the long foot edge, 20° (Held).
  const Region base{{{0, 0, 0}, {150, 0, 0}, {150, 30, 0}, {30, 30, 0}, {30, 80, 0}, {0, 80, 0}}, {}};
  const Region r = rotated(base, 20);
  ZigzagParams zp;
  zp.angle_deg = std::nullopt;
  std::vector<AngleScore> scores;
  const PlanResult p = plan_zigzag(r, tool10(), zp, &scores);
  ASSERT_EQ(p.status, PlanStatus::Ok);
  EXPECT_NEAR(std::get<ZigzagStats>(p.stats).angle_deg, 20.0, 1e-9);
  EXPECT_EQ(std::get<ZigzagStats>(p.stats).regions, 1);
  int one = 0, two = 0;
  for (const auto& s : scores) {
    const double rel = std::fmod(s.angle_deg - 20 + 360, 180.0);  // direction in the L's own frame
    if (rel > 1e-6 && rel < 90 - 1e-6) {
      EXPECT_EQ(s.regions, 1) << s.angle_deg;
      ++one;
    }
    if (rel > 90 + 1e-6 && rel < 180 - 1e-6) {
      EXPECT_EQ(s.regions, 2) << s.angle_deg;
      ++two;
    }
  }
  EXPECT_GT(one, 10);
  EXPECT_GT(two, 10);
  EXPECT_LT(angle_diff(std::get<ZigzagStats>(p.stats).angle_deg, 20), 1e-9);
}

TEST(DirectionSearch, FixedAngleIsUsedAsGiven) {
  const Region r{{{0, 0, 0}, {100, 0, 0}, {100, 60, 0}, {0, 60, 0}}, {}};
  ZigzagParams zp;
  zp.angle_deg = 37.5;
  const PlanResult p = plan_zigzag(r, tool10(), zp);
  EXPECT_EQ(std::get<ZigzagStats>(p.stats).angle_deg, 37.5);
  EXPECT_EQ(std::get<ZigzagStats>(p.stats).angles_tried, 1U);
  EXPECT_EQ(p.planner, "zigzag-t");
  // Deterministic: the same input gives the same path, vertex for vertex.
  const PlanResult q = plan_zigzag(r, tool10(), zp);
  ASSERT_EQ(p.path.chains.size(), q.path.chains.size());
  for (std::size_t c = 0; c < p.path.chains.size(); ++c) {
    ASSERT_EQ(p.path.chains[c].pts.size(), q.path.chains[c].pts.size());
    for (std::size_t k = 0; k < p.path.chains[c].pts.size(); ++k) {
      EXPECT_EQ(p.path.chains[c].pts[k].x, q.path.chains[c].pts[k].x);
      EXPECT_EQ(p.path.chains[c].pts[k].y, q.path.chains[c].pts[k].y);
    }
  }
}
