// Finishing work estimates (finish/work.hpp, issue 12 §1) against hand-computed counts, and the
// guard in plan_finish: refused over the limit, run at exactly the estimate.
#include "millnet/core/error.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/finish/work.hpp"

#include "ingest/builders.hpp"

#include <gtest/gtest.h>

#include <string>

namespace millnet::finish {
using tooling::Cutter;
using tooling::CutterType;
namespace {

FinishParams params(double stepover) {
  FinishParams p;
  p.tool = Cutter::ball(2);
  p.stepover_mm = stepover;
  p.step_down_mm = 0.5;
  p.safe_z_mm = 15;
  return p;
}

}  // namespace

TEST(FinishWork, CountsOfEachGridOverA60By40Box) {
  const auto e = estimate_work(0, 0, 60, 40, all_strategies(), params(0.2));
  ASSERT_EQ(e.size(), 4U);
  // Raster: ⌈40 / 0.2⌉ + 1 = 201 passes × (⌈60 / 0.1⌉ + 1 = 601) first samples (h0 = min(0.1, R/4)).
  EXPECT_EQ(e[0].unit, "raster CL points");
  EXPECT_EQ(e[0].count, 201.0 * 601.0);
  EXPECT_EQ(e[0].cause, "stepover 0.2 mm over a 60 × 40 mm machining boundary");
  // Scallop mode: passes 2·√(0.005 · (2 − 0.005)) = 0.19975 mm apart: ⌈40 / 0.19975⌉ + 1 = 202 × 601.
  EXPECT_EQ(e[1].unit, "scallop-mode CL points");
  EXPECT_EQ(e[1].count, 202.0 * 601.0);
  EXPECT_EQ(e[1].cause, "scallop 0.005 mm (passes 0.19975 mm apart) over a 60 × 40 mm machining boundary");
  // Waterline grid at min(0.25, R/2) = 0.25: 241 × 161.
  EXPECT_EQ(e[2].unit, "waterline CL grid points");
  EXPECT_EQ(e[2].count, 241.0 * 161.0);
  // Equidistant grid at min(0.1, p_f/2) = 0.1: 601 × 401.
  EXPECT_EQ(e[3].unit, "equidistant grid points");
  EXPECT_EQ(e[3].count, 601.0 * 401.0);
  // One strategy, one grid; raster at 90° swaps along and across.
  FinishParams p = params(0.2);
  p.raster_angle_deg = 90;
  const auto r = estimate_work(0, 0, 60, 40, {Strategy::Raster}, p);
  ASSERT_EQ(r.size(), 1U);
  EXPECT_NEAR(r[0].count, 301.0 * 401.0, 0.5);
}

TEST(FinishWork, PlanFinishRefusesOverTheLimitAndRunsAtIt) {
  const ingest::Mesh mesh = testing_ingest::box(0, 0, 0, 20, 10, 5);
  const DropCutter dc(mesh, Cutter::ball(2));
  FinishParams p = params(0.5);
  // ⌈10 / 0.5⌉ + 1 = 21 passes × (⌈20 / 0.1⌉ + 1 = 201) = 4,221 raster CL points.
  const double n = estimate_work(0, 0, 20, 10, {Strategy::Raster}, p)[0].count;
  ASSERT_EQ(n, 21.0 * 201.0);
  p.limits.max_work = n - 1;
  try {
    (void)plan_finish(mesh, dc, Strategy::Raster, p);
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("stepover 0.5 mm over a 20 × 10 mm machining boundary makes 4.221e3 raster CL "
                                         "points (≈ 101 kB); the limit is 4.220e3 (--max-work, /limits/max_work)"),
              std::string::npos)
        << e.what();
  }
  p.limits.max_work = n;
  EXPECT_FALSE(plan_finish(mesh, dc, Strategy::Raster, p).passes.empty());
}

// Issue 42 §7: scallop 1e-9 spaced scallop mode's passes 8.9e-5 mm apart with no estimate (a hang);
// it is refused before a pass is sampled, naming the scallop and the spacing it makes.
TEST(FinishWork, ScallopModeIsEstimatedAtItsPassSpacing) {
  const ingest::Mesh mesh = testing_ingest::box(0, 0, 0, 20, 10, 5);
  const DropCutter dc(mesh, Cutter::ball(2));
  FinishParams p = params(0.2);
  p.scallop_mm = 1e-9;
  try {
    (void)plan_finish(mesh, dc, Strategy::ScallopMode, p);
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scallop 1e-09 mm (passes 0.000089442719 mm apart) over a 20 × 10 mm "
                                         "machining boundary makes 2.2e7 scallop-mode CL points"),
              std::string::npos)
        << e.what();
  }
  // A real scallop runs within its estimate: the CL points it holds are no more than counted.
  p.scallop_mm = 0.005;
  const double n = estimate_work(0, 0, 20, 10, {Strategy::ScallopMode}, p)[0].count;
  p.limits.max_work = n;
  EXPECT_FALSE(plan_finish(mesh, dc, Strategy::ScallopMode, p).passes.empty());
}

}  // namespace millnet::finish
