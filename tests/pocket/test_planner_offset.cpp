// The offset (contour-parallel) planner: every bench pocket cleared with the tool down, no gouge
// (independent G-code replay), nothing reachable left uncut; offsets that split, a region too
// narrow for a helix, an island that touches the first ring, two components, direction.
#include "testing/program_text.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace millnet::pocket;
using millnet::testing::to_replay;
namespace {

CutParams bench_cut() { return millnet::testing::issue11_bench_cut(); }

struct Outcome {
  PlanResult plan;
  MachiningResult m;
  millnet::testing::ReplayResult rep;
  std::size_t uncovered = 0;  ///< grid points a centred tool could reach that no cutting move swept
  std::size_t probed = 0;
};

/// Plans, machines (helix entry), replays the G-code and checks coverage independently of the
/// planner: every point of a 0.5 mm grid where the tool fits with 0.2 mm to spare (so it is
/// certainly reachable) must lie within R + 0.01 mm of a replayed cutting move sampled every 0.25 mm
/// (a missing ring leaves points up to a stepover farther).
Outcome run(const Region& region, const CutParams& cut, bool climb = true) {
  Outcome o;
  o.plan = plan(region, cut, OffsetSpec{OffsetParams{climb}});
  MachiningOptions opt;
  opt.entry = Entry::Helix;
  opt.contour = true;
  o.m = machine_pocket(region, cut, o.plan, opt);
  if (o.m.status != PlanStatus::Ok) return o;
  o.rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(o.m.program), cut.safe_z);
  millnet::testing::check_gouge(o.rep, to_replay(region), cut.tool.diameter / 2);
  o.uncovered = millnet::testing::unswept_points(o.rep, region, cut.tool.diameter / 2, o.probed);
  return o;
}

Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }
Loop circle_cw(double cx, double cy, double r) { return {{cx - r, cy, -1}, {cx + r, cy, -1}}; }
}  // namespace

class OffsetBench : public ::testing::TestWithParam<const char*> {};

TEST_P(OffsetBench, ClearsWithTheToolDownAndNoGouge) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + GetParam() + ".json");
  const CutParams cut = bench_cut();
  const Outcome o = run(pf.region, cut);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_TRUE(o.plan.walls_cut);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_LT(o.rep.worst_mm, 0.01);
  // One reachable component each: not a single retraction, one entry.
  const auto& st = std::get<OffsetStats>(o.plan.stats);
  EXPECT_EQ(st.components, 1u);
  EXPECT_EQ(o.m.metrics.retractions, 0);
  EXPECT_EQ(o.rep.retractions, 0);
  EXPECT_EQ(o.m.metrics.plunges, 1);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_GT(o.probed, 1000u);
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_GT(o.m.metrics.time_kinematic_min, o.m.path.cut_length() / 1500);  // never faster than the feed
}

INSTANTIATE_TEST_SUITE_P(Pockets, OffsetBench, ::testing::Values("four_islands", "comb", "eight_islands"));

TEST(PlannerOffset, OffsetsThatSplitAreLinkedWithTheToolDown) {
  // Two 40 mm rooms joined by a 14 mm corridor: the tool (Ø10) passes, the offsets split in two.
  Region r;
  r.boundary = {{0, 0, 0},    {40, 0, 0},  {40, 13, 0}, {70, 13, 0}, {70, 0, 0},  {110, 0, 0},
                {110, 40, 0}, {70, 40, 0}, {70, 27, 0}, {40, 27, 0}, {40, 40, 0}, {0, 40, 0}};
  validate_and_normalize(r, "test");
  const Outcome o = run(r, bench_cut());
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  const auto& st = std::get<OffsetStats>(o.plan.stats);
  EXPECT_GE(st.splits, 1u);
  EXPECT_EQ(st.components, 1u);
  EXPECT_EQ(o.m.metrics.retractions, 0);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
}

TEST(PlannerOffset, ANeckTheToolCannotPassMakesTwoComponentsAndOneRetraction) {
  // The same rooms joined by an 8 mm neck: a Ø10 tool cannot pass, so two components.
  Region r;
  r.boundary = {{0, 0, 0},    {40, 0, 0},  {40, 16, 0}, {70, 16, 0}, {70, 0, 0},  {110, 0, 0},
                {110, 40, 0}, {70, 40, 0}, {70, 24, 0}, {40, 24, 0}, {40, 40, 0}, {0, 40, 0}};
  validate_and_normalize(r, "test");
  const Outcome o = run(r, bench_cut());
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  EXPECT_EQ(std::get<OffsetStats>(o.plan.stats).components, 2u);
  EXPECT_EQ(o.m.metrics.retractions, 1);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.uncovered, 0u);
}

TEST(PlannerOffset, ARegionTooNarrowForAHelixStillEntersAndClears) {
  // A 12 mm slot: the tool centre has a 2 mm wide strip, no room for a helix; the entry falls back
  // to a ramp along the ring and the slot is still cut end to end without touching its walls.
  Region r;
  r.boundary = rect(0, 0, 80, 12);
  validate_and_normalize(r, "test");
  const Outcome o = run(r, bench_cut());
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.m.metrics.retractions, 0);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_NEAR(o.m.metrics.reachable_area_mm2, 80 * 12 - (4 - M_PI) * 25, 0.5);  // four rounded corners
}

TEST(PlannerOffset, AnIslandTouchingTheFirstRing) {
  // The island's grown ring touches the wall's first ring (10 mm = 2 × clearance between them).
  Region r;
  r.boundary = rect(0, 0, 100, 80);
  r.islands = {circle_cw(50, 20, 10)};
  validate_and_normalize(r, "test");
  const Outcome o = run(r, bench_cut());
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.m.metrics.retractions, 0);
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
}

TEST(PlannerOffset, ClimbRunsTheWallCounterClockwiseAndConventionalReverses) {
  Region r;
  r.boundary = rect(0, 0, 60, 40);
  validate_and_normalize(r, "test");
  const CutParams cut = bench_cut();
  auto wall_area = [&](bool climb) {
    // The last ring of the only chain is the wall ring (inside out): its signed area.
    const PlanResult p = plan_offset(r, cut, OffsetParams{climb});
    const auto& pts = p.path.chains.back().pts;
    const std::size_t n = 4 * 0 + pts.size();
    double a = 0;
    for (std::size_t k = n - 1 - 4; k + 1 < n; ++k) a += pts[k].x * pts[k + 1].y - pts[k + 1].x * pts[k].y;
    return a;
  };
  EXPECT_GT(wall_area(true), 0);
  EXPECT_LT(wall_area(false), 0);
}
