// Issue 37 §1's property: on every program the five strategies write for a part made for it (45°
// flanks and a plateau) with a ball, the z-map's
// gouge verdict after its exact check (job::score_program: the 16 deepest z-map places) and an
// exact check of the WHOLE program (every move swept against the part's triangles) agree — no
// strategy gouges, every z-map gouge place is an artefact the check refutes — and a program pushed
// 0.05 mm into the plateau at one point is a gouge for both, of the same depth within a cell's
// profile error. (A ball: the exact check of a bull samples its disk, ~1,250 probes a position, and
// took 103 s on this one place.) The same on a plate with a steep-walled boss and a blind bore, where
// cells straddle the walls, and for a rest program there.
#include "millnet/finish/rest.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/job/finishing.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/simulate/exact_gouge.hpp"

#include "ingest/builders.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <variant>

namespace millnet::job {
namespace {

using tooling::Cutter;

ingest::Mesh flanks() {  // plateau z 8 for |d|∞ ≤ 2 around (8, 8), 45° flanks to a shelf at 0.5
  return testing_ingest::solid(
      [](double x, double y) { return std::clamp(8 - (std::max(std::abs(x - 8), std::abs(y - 8)) - 2), 0.5, 8.0); }, 0,
      16, 0, 16, 32, 32);
}

constexpr double kWholeProgramTolMm = 0.005;

struct Case {
  Scored scored;
  simulate::Penetration exact;  ///< the whole program against the triangles
};

SimParams sim() {
  SimParams s;
  s.cell_mm = 0.05;
  return s;
}

/// The program machined and scored as `finish --simulate` does, and swept exactly move by move.
/// `window` > 0: only the moves' parts within it of (cx, cy) are swept exactly (a bull's disk is
/// sampled, ~1,250 probes per position: a whole program would take minutes).
Case check(const ingest::Mesh& mesh, const Frame& frame, const Design& design, const gcode::Program& program,
           const Cutter& cutter, double cx = 0, double cy = 0, double window = 0) {
  Case c;
  c.scored = score_program(design, frame, program, cutter, sim());
  const simulate::PartSolid solid(mesh, frame.z_shift());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<gcode::Point3> starts = simulate::item_starts(program, {nan, nan, nan});
  std::vector<std::size_t> items;
  for (std::size_t i = 0; i < program.items.size(); ++i)  // O(items)
    if (std::holds_alternative<gcode::Move>(program.items[i])) items.push_back(i);
  // The whole program at the gouge tolerance would need a probe every 2 µm of path in contact; 5 µm
  // (2.5× the tolerance, 1 % of the 0.05 mm pushed below) keeps it to seconds.
  simulate::ExactGougeOptions o = sim().gouge_options();
  o.tolerance_mm = kWholeProgramTolMm;
  c.exact = simulate::sweep_penetration(solid, program, starts, items, cutter, cx, cy, window, o);
  return c;
}

void expect_strategies_agree(const ingest::Mesh& mesh, const Cutter& cutter) {
  const Frame frame = frame_of(mesh, 1.0);
  const Design design = design_surface(mesh, frame, sim());
  finish::FinishParams p;
  p.tool = cutter;
  p.stepover_mm = 1;
  p.step_down_mm = 1;
  p.safe_z_mm = 5;
  p.z_shift = frame.z_shift();
  const finish::DropCutter dc(mesh, cutter);
  for (const finish::FinishPlan& plan : finish::plan_finish(mesh, dc, finish::all_strategies(), p)) {
    SCOPED_TRACE(finish::strategy_name(plan.strategy) + ", " + cutter.describe());
    const Case c = check(mesh, frame, design, plan.program, cutter);
    EXPECT_FALSE(c.scored.metrics.gouged) << c.scored.metrics.max_gouge_mm;
    EXPECT_LE(c.exact.depth_mm, kWholeProgramTolMm) << "the whole program against the triangles, item " << c.exact.item;
    EXPECT_EQ(c.scored.metrics.gouged, c.exact.depth_mm > kWholeProgramTolMm);
    EXPECT_EQ(c.scored.metrics.gouge_places_refuted, c.scored.metrics.gouge_places_checked);
    EXPECT_LE(c.scored.metrics.max_gouge_mm, sim().tolerance_mm);
  }
}

TEST(GougeProperty, EveryStrategysProgramIsJudgedAlikeByTheZMapAndByTheWholeProgramAgainstTheTriangles) {
  expect_strategies_agree(flanks(), Cutter::ball(2));
}

/// Where the cells lie most (issue 37 §1): a plate (z 2) with a boss (z 6) whose walls stand over
/// one 0.5 mm sampling step (83°) and a blind bore (Ø4 down to z 0.5) with walls as steep: cells
/// straddle every wall.
ingest::Mesh boss_and_bore() {
  return testing_ingest::solid(
      [](double x, double y) {
        if (std::max(std::abs(x - 5), std::abs(y - 5)) < 2) return 6.0;
        if (std::hypot(x - 11, y - 11) < 2) return 0.5;
        return 2.0;
      },
      0, 16, 0, 16, 32, 32);
}

TEST(GougeProperty, OnSteepWallsAndInABoreTheZMapAndTheWholeProgramAgreeToo) {
  expect_strategies_agree(boss_and_bore(), Cutter::ball(2));
}

// A rest program (a Ø1 ball behind a Ø3 reference, in the boss's and the bore's concave feet) is
// judged alike as well: its pieces, entries just over the stock and stay-down links included.
TEST(GougeProperty, ARestProgramIsJudgedAlikeByTheZMapAndByTheWholeProgram) {
  const ingest::Mesh mesh = boss_and_bore();
  const Frame frame = frame_of(mesh, 1.0);
  const Design design = design_surface(mesh, frame, sim());
  const Cutter small = Cutter::ball(1);
  finish::FinishParams p;
  p.tool = small;
  p.stepover_mm = 0.25;
  p.step_down_mm = 0.25;
  p.safe_z_mm = 5;
  p.z_shift = frame.z_shift();
  const finish::DropCutter dc(mesh, small);
  finish::RestParams rp;
  rp.reference = Cutter::ball(3);
  const finish::RestRegions r = finish::rest_regions(mesh, dc, rp);
  ASSERT_FALSE(r.empty());
  const finish::FinishPlan plan = finish::plan_rest(mesh, dc, r, rp.reference.describe(), p);
  ASSERT_GT(plan.path_length_mm, 10);
  const Case c = check(mesh, frame, design, plan.program, small);
  EXPECT_LE(c.exact.depth_mm, kWholeProgramTolMm) << "item " << c.exact.item;
  EXPECT_EQ(c.scored.metrics.gouged, c.exact.depth_mm > kWholeProgramTolMm);
  EXPECT_EQ(c.scored.metrics.gouge_places_refuted, c.scored.metrics.gouge_places_checked);
}

TEST(GougeProperty, AProgramPushedIntoThePlateauIsAGougeOfTheSameDepthForBoth) {
  const ingest::Mesh mesh = flanks();
  const Frame frame = frame_of(mesh, 1.0);
  const Design design = design_surface(mesh, frame, sim());
  {
    const Cutter cutter = Cutter::ball(2);
    finish::FinishParams p;
    p.tool = cutter;
    p.stepover_mm = 0.5;
    p.safe_z_mm = 5;
    p.z_shift = frame.z_shift();
    const finish::DropCutter dc(mesh, cutter);
    gcode::Program program = finish::plan_finish(mesh, dc, finish::Strategy::Raster, p).program;
    // The first feed move along the plateau (both ends at its height, over its middle): a point
    // 0.05 mm below its midpoint is put in its way.
    const double top = 8 + frame.z_shift();
    gcode::Point3 at{0, 0, 0}, dip{};
    double run = 0;  // from either end to the dip
    bool found = false;
    for (std::size_t i = 0; i < program.items.size() && !found; ++i) {
      const auto* m = std::get_if<gcode::Move>(&program.items[i]);
      if (m == nullptr) continue;
      const double mx = (at[0] + m->to[0]) / 2, my = (at[1] + m->to[1]) / 2;
      const bool on_plateau = std::abs(at[2] - top) < 1e-6 && std::abs(m->to[2] - top) < 1e-6 &&
                              std::abs(mx - 8) <= 1 && std::abs(my - 8) <= 1;
      if (m->motion == gcode::Motion::Line && on_plateau && std::hypot(m->to[0] - at[0], m->to[1] - at[1]) > 0.5) {
        gcode::Move d = *m;
        d.to = {mx, my, top - 0.05};
        dip = d.to;
        run = std::hypot(m->to[0] - at[0], m->to[1] - at[1]) / 2;
        program.items.insert(program.items.begin() + static_cast<std::ptrdiff_t>(i), d);
        found = true;
      }
      at = m->to;
    }
    ASSERT_TRUE(found);
    const Case c = check(mesh, frame, design, program, cutter, dip[0], dip[1], cutter.radius() + 0.1);
    ASSERT_TRUE(c.scored.metrics.gouged);
    EXPECT_NEAR(c.exact.depth_mm, 0.05, 5e-4);                           // the swept cutter, exact
    EXPECT_NEAR(c.scored.metrics.max_gouge_mm, c.exact.depth_mm, 1e-3);  // confirmed: the check's depth
    // The cells: the one nearest the dip lies within half a cell's diagonal h of it, where the V's
    // flanks (slope 0.05 / run) and the cutter's profile leave at most h·0.05/run + f(h) more.
    const double h = 0.5 * std::sqrt(2.0) * sim().cell_mm;
    const double f = cutter.profile_height(std::min(h, cutter.radius()));
    EXPECT_LE(c.scored.metrics.zmap_max_gouge_mm, 0.05 + 1e-9);
    EXPECT_GE(c.scored.metrics.zmap_max_gouge_mm, 0.05 - h * 0.05 / run - f);
    EXPECT_NEAR(c.scored.metrics.gouge_x_mm, dip[0], 0.03);
    EXPECT_NEAR(c.scored.metrics.gouge_y_mm, dip[1], 0.03);
  }
}

}  // namespace
}  // namespace millnet::job
