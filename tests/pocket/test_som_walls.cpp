// The SOM planner clearing a pocket by itself (issue 11): wall rings spliced into the tour with the
// tool down, corners blended by tangent arcs. Corner blending by hand (a 90° corner: tangent
// points, radius, bulge, no overcut), its limits (coverage deviation, neighbour segments, move_ok,
// non-blendable vertices), the motion model's gain on a blended square; every bench pocket with the
// SOM alone (no contour pass): no gouge in an independent G-code replay at 0.01 mm, nothing
// reachable left uncut (Clipper metric and an independent probe grid), no retraction beyond the
// reachable components − 1, planned within 1 s, deterministic, and faster than before.
#include "testing/program_text.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/tolerances.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

using namespace millnet::pocket;
using millnet::testing::to_replay;

namespace {

const MoveOk kFree = [](const Vec2&, const Vec2&) { return true; };

Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }

/// Largest distance from sample points of the polyline `pts` to the path `v` (bulges honoured),
/// and the smallest distance from the path to a point `p` — by dense sampling (independent of
/// blend_corners' own geometry).
std::vector<Vec2> sample(const std::vector<Vertex>& v, double step) {
  std::vector<Vec2> s;
  for (std::size_t k = 0; k + 1 < v.size(); ++k) {
    const Segment seg{v[k].p(), v[k + 1].p(), v[k].bulge};
    const int n = std::max(1, static_cast<int>(std::ceil(length(seg) / step)));
    for (int i = 0; i <= n; ++i) s.push_back(point_at(seg, static_cast<double>(i) / n));
  }
  return s;
}
double dist_to(const std::vector<Vec2>& s, const Vec2& p) {
  double best = 1e300;
  for (const Vec2& q : s) best = std::min(best, (q - p).norm());
  return best;
}

}  // namespace

// A left turn of 90° at P = (10, 0) from A = (0, 0) to B = (10, 10), radius 2: tangent points
// (8, 0) and (10, 2), centre (8, 2), bulge tan(90°/4) = √2 − 1, the arc's midpoint
// 2·(√2 − 1) = 0.8284 mm from P. A right turn mirrors it (bulge < 0).
TEST(CornerBlend, NinetyDegreeCornerByHand) {
  CornerBlendParams bp;
  bp.max_radius_mm = 2;
  bp.max_deviation_mm = 1;
  CornerBlendStats st;
  const auto v = blend_corners({{0, 0}, {10, 0}, {10, 10}}, {0, 1, 0}, bp, kFree, &st);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_NEAR(v[0].x, 0, 1e-12);
  EXPECT_EQ(v[0].bulge, 0.0);
  EXPECT_NEAR(v[1].x, 8, 1e-12);
  EXPECT_NEAR(v[1].y, 0, 1e-12);
  EXPECT_NEAR(v[1].bulge, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(v[2].x, 10, 1e-12);
  EXPECT_NEAR(v[2].y, 2, 1e-12);
  EXPECT_EQ(v[2].bulge, 0.0);
  EXPECT_NEAR(v[3].y, 10, 1e-12);
  const Arc a = arc_of(Segment{v[1].p(), v[2].p(), v[1].bulge});
  EXPECT_NEAR(a.center.x(), 8, 1e-12);
  EXPECT_NEAR(a.center.y(), 2, 1e-12);
  EXPECT_NEAR(a.radius, 2, 1e-12);
  EXPECT_NEAR(a.sweep, M_PI / 2, 1e-12);
  EXPECT_EQ(st.corners, 1);
  EXPECT_EQ(st.blended, 1);
  // The arc never leaves the corner's triangle (no overcut beyond the sharp path's own sweep) and
  // passes 2(√2 − 1) from P.
  const auto s = sample(v, 0.01);
  for (const Vec2& q : s) {
    EXPECT_LE(q.x(), 10 + 1e-9);
    EXPECT_GE(q.y(), -1e-9);
  }
  EXPECT_NEAR(dist_to(s, {10, 0}), 2 * (std::sqrt(2.0) - 1), 1e-3);

  const auto r = blend_corners({{0, 0}, {10, 0}, {10, -10}}, {0, 1, 0}, bp, kFree);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_NEAR(r[1].bulge, -(std::sqrt(2.0) - 1), 1e-12);
  EXPECT_NEAR(r[2].y, -2, 1e-12);
}

TEST(CornerBlend, RadiusLimitedByDeviationNeighboursAndMoveOk) {
  CornerBlendParams bp;
  bp.max_radius_mm = 10;
  bp.max_deviation_mm = 0.5;  // r(√2 − 1) ≤ 0.5 ⇒ r ≤ 1.2071
  auto v = blend_corners({{0, 0}, {10, 0}, {10, 10}}, {0, 1, 0}, bp, kFree);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_NEAR(10 - v[1].x, 0.5 / (std::sqrt(2.0) - 1), 1e-9);
  // Short segments: tangent length ≤ half of each (here 1 ⇒ r = 1 at 90°).
  bp.max_deviation_mm = 10;
  v = blend_corners({{0, 0}, {2, 0}, {2, 10}}, {0, 1, 0}, bp, kFree);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_NEAR(v[1].x, 1, 1e-9);
  // A chord A'B' that move_ok refuses halves r; a chord never free keeps the corner sharp.
  bp.max_radius_mm = 2;
  const MoveOk short_only = [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1.5; };
  v = blend_corners({{0, 0}, {10, 0}, {10, 10}}, {0, 1, 0}, bp, short_only);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_NEAR(v[1].x, 9, 1e-9);  // r = 1: chord √2 < 1.5
  const MoveOk never = [](const Vec2&, const Vec2&) { return false; };
  v = blend_corners({{0, 0}, {10, 0}, {10, 10}}, {0, 1, 0}, bp, never);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[1].bulge, 0.0);
}

TEST(CornerBlend, SharpWhereNotBlendableReversedOrStraight) {
  CornerBlendParams bp;
  CornerBlendStats st;
  // not blendable
  auto v = blend_corners({{0, 0}, {10, 0}, {10, 10}}, {1, 0, 1}, bp, kFree, &st);
  EXPECT_EQ(v.size(), 3u);
  EXPECT_EQ(st.blended, 0);
  // a reversal stays a point
  v = blend_corners({{0, 0}, {10, 0}, {0, 0}}, {0, 1, 0}, bp, kFree, &st);
  EXPECT_EQ(v.size(), 3u);
  // straight on: merged, the path is one move
  v = blend_corners({{0, 0}, {5, 0}, {10, 0}, {10, 5}}, {0, 1, 0, 0}, bp, kFree, &st);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(st.merged, 1);
  EXPECT_NEAR(v[1].x, 10, 1e-12);
  // consecutive blends meeting at a segment's middle share the vertex (no zero-length move)
  bp.max_radius_mm = 5;
  bp.max_deviation_mm = 5;
  v = blend_corners({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {0, 1, 1, 0}, bp, kFree, &st);
  EXPECT_EQ(st.blended, 2);
  ASSERT_EQ(v.size(), 5u);  // (0,0) (5,0)⌒(10,5)⌒(5,10) (0,10)
  EXPECT_NEAR(v[2].y, 5, 1e-12);
  EXPECT_GT(v[1].bulge, 0);
  EXPECT_GT(v[2].bulge, 0);
}

// The motion model (500 mm/s², δ 0.01 mm, 1500 mm/min): a 60 mm square loop cut with sharp corners
// stops to ≈ 3.5 mm/s at each; blended with 2.5 mm arcs it keeps (nearly) the feed.
TEST(CornerBlend, ABlendedSquareIsFasterOnTheMachine) {
  Region region;
  region.boundary = rect(-10, -10, 90, 90);
  validate_and_normalize(region, "test");
  const CutParams cut = millnet::testing::issue11_bench_cut();
  std::vector<Vec2> sq;
  for (int lap = 0; lap < 3; ++lap)
    for (const Vec2& p : {Vec2(10, 10), Vec2(70, 10), Vec2(70, 70), Vec2(10, 70)}) sq.push_back(p);
  sq.push_back({10, 10});
  const Clearance clear(region, cut.clearance());
  const MoveOk ok = [&](const Vec2& a, const Vec2& b) { return clear.move_ok(a, b); };
  auto time_of = [&](const std::vector<Vertex>& v) {
    LevelPlan L;
    L.z = -5;
    L.region = region;
    Chain c;
    c.pts = v;
    L.path.chains.push_back(c);
    MachiningOptions opt;
    opt.entry = Entry::Predrill;
    return machine_levels({L}, cut, opt).metrics.time_kinematic_min;
  };
  std::vector<Vertex> sharp;
  for (const Vec2& p : sq) sharp.push_back({p.x(), p.y(), 0});
  CornerBlendParams bp;
  bp.max_radius_mm = 2.5;
  bp.max_deviation_mm = 2;
  std::vector<char> flags(sq.size(), 1);
  CornerBlendStats st;
  const auto blended = blend_corners(sq, flags, bp, ok, &st);
  EXPECT_EQ(st.blended, 11);  // every corner but the two ends
  const double t_sharp = time_of(sharp), t_blend = time_of(blended);
  EXPECT_LT(t_blend, t_sharp);
  // 11 corners × (decelerate 25 → 3.47 mm/s and back at 500 mm/s²: ≈ 0.037 s lost each) ≈ 0.4 s
  EXPECT_GT((t_sharp - t_blend) * 60, 0.3);
}

namespace {

struct Outcome {
  PlanResult plan;
  MachiningResult m;
  millnet::testing::ReplayResult rep;
  std::size_t uncovered = 0, probed = 0;
  std::size_t components = 0;
};

/// SOM alone (defaults: walls and corner arcs), machined with the contour pass asked for (it must
/// not be added: walls_cut), the G-code replayed independently; coverage probed on a 0.5 mm grid
/// (as test_planner_offset.cpp): every point where the tool fits with 0.2 mm to spare must lie
/// within R + 0.01 mm of a replayed cutting move.
Outcome run(const Region& region, const CutParams& cut, Entry entry) {
  Outcome o;
  SomSpec spec;
  spec.frame = GridFrame{{0, 0}, 0, cut.stepover};
  o.plan = plan(region, cut, spec);
  MachiningOptions opt;
  opt.entry = entry;
  opt.contour = true;
  opt.machine = millnet::gcode::MotionModel{5000, 5000, 500, 0.01};
  o.m = machine_pocket(region, cut, o.plan, opt);
  o.components = offset_inward(region, cut.clearance() + tol::contour_margin_mm, tol::contour_chord_mm).size();
  if (o.m.status != PlanStatus::Ok) return o;
  o.rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(o.m.program), cut.safe_z);
  millnet::testing::check_gouge(o.rep, to_replay(region), cut.tool.diameter / 2);
  o.uncovered = millnet::testing::unswept_points(o.rep, region, cut.tool.diameter / 2, o.probed);
  return o;
}

}  // namespace

class SomAloneBench : public ::testing::TestWithParam<const char*> {};

// Issue 11's bench (configs/bench/roughing-issue11.json).
TEST_P(SomAloneBench, ClearsThePocketByItselfWithoutGouge) {
  const std::string name = GetParam();
  const Region region = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json").region;
  const CutParams cut = millnet::testing::issue11_bench_cut();
  const Outcome o = run(region, cut, Entry::Helix);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_TRUE(o.plan.walls_cut);
  for (const Chain& c : o.m.path.chains) EXPECT_EQ(c.role, "cut");  // no contour pass added
  const auto& st = std::get<SomStats>(o.plan.stats);
  EXPECT_GT(st.wall_rings, 0u);
  EXPECT_EQ(st.wall_ring_links, st.wall_rings);
  EXPECT_GT(st.corner_arcs, 0u);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_LT(o.rep.worst_mm, 0.01);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_GT(o.probed, 1000u);
  EXPECT_EQ(o.uncovered, 0u);
  ASSERT_GE(o.components, 1u);
  EXPECT_LE(o.m.metrics.retractions, static_cast<double>(o.components - 1));
  EXPECT_LE(o.rep.retractions, static_cast<int>(o.components - 1));
  EXPECT_GT(o.m.metrics.time_kinematic_min, o.m.path.cut_length() / 1500);  // never faster than the feed
  // Deterministic.
  const Outcome again = run(region, cut, Entry::Helix);
  EXPECT_EQ(millnet::testing::linuxcnc_text(again.m.program), millnet::testing::linuxcnc_text(o.m.program));
}

// The SOM alone against FreeCAD 0.20's offset pocket with its default entry, a plunge into a
// pre-drilled hole (scripts/bench_roughing.sh "predrill"): 1.49 / 1.41 / 2.65 min.
TEST_P(SomAloneBench, NoSlowerThanFreeCadsOffsetPocket) {
  const std::string name = GetParam();
  const std::map<std::string, double> freecad{{"four_islands", 1.49}, {"comb", 1.41}, {"eight_islands", 2.65}};
  const Region region = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json").region;
  const CutParams cut = millnet::testing::issue11_bench_cut();
  const Outcome o = run(region, cut, Entry::Predrill);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_LE(o.m.metrics.time_kinematic_min, freecad.at(name)) << name;
}

INSTANTIATE_TEST_SUITE_P(Pockets, SomAloneBench, ::testing::Values("four_islands", "comb", "eight_islands"));

// The seed's planner stays what it was with both switches off: grid points only, no arcs, and the
// wall pass is machine_pocket's.
TEST(SomAlone, BothSwitchesOffIsTheSeedsPlanner) {
  const Region region = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/four_islands.json").region;
  const CutParams cut = millnet::testing::issue11_bench_cut();
  const GridFrame frame{{0, 0}, 0, cut.stepover};
  const auto seed = plan_som(region, cut, frame, {}, {}, SomPathParams{.walls = false, .blend_corners = false});
  EXPECT_FALSE(seed.walls_cut);
  EXPECT_EQ(seed.tool_points.pts.size(), make_tool_points(region, frame, cut.clearance()).pts.size());
  for (const Chain& c : seed.path.chains)
    for (const Vertex& v : c.pts) EXPECT_EQ(v.bulge, 0.0);
  const auto now = plan_som(region, cut, frame, {}, {});
  EXPECT_TRUE(now.walls_cut);
  EXPECT_LT(now.tool_points.pts.size(), seed.tool_points.pts.size());  // the rings sweep the first row
}

// A pocket too narrow for any grid point (a 14 mm slot, Ø10: the tool centre has a 4 mm strip)
// but wide enough for the tool: the seed's planner finds no tool point; with walls the ring cuts it.
TEST(SomAlone, ASlotWithoutGridPointsIsCutByItsRing) {
  Region region;
  region.boundary = rect(0.5, 0.5, 60.5, 14.5);
  validate_and_normalize(region, "test");
  const CutParams cut = millnet::testing::issue11_bench_cut();
  const GridFrame frame{{0, 0}, 0, cut.stepover};
  const auto seed = plan_som(region, cut, frame, {}, {}, SomPathParams{.walls = false, .blend_corners = false});
  EXPECT_EQ(seed.status, PlanStatus::NoToolPoints);
  const Outcome o = run(region, cut, Entry::Helix);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 0.5);
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_EQ(o.m.metrics.retractions, 0);
}
