// The five finishing strategies on meshes built in code: the path never goes below the
// drop-cutter (brute-force oracle), and each strategy's own property (raster passes and heights,
// waterline points on their level within the tolerance, scallop-mode spacing from the 3D stepover,
// equidistant loops at multiples of p_f from the boundary, slope-mode split by angle), plus
// thread-count invariance and the parameter checks.
#include "millnet/core/error.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/finish/tolerances.hpp"

#include "ingest/builders.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <variant>

namespace millnet::finish {
using tooling::Cutter;
using tooling::CutterType;
namespace {

using testing_ingest::box;
using testing_ingest::solid;

/// Plateau at z = 8 (|d|∞ ≤ 2 around (10, 10)), 45° flanks down to a 0.5 mm shelf, base at 0.
ingest::Mesh pyramid() {
  return solid(
      [](double x, double y) {
        const double r = std::max(std::abs(x - 10), std::abs(y - 10));
        return std::clamp(8 - (r - 2), 0.5, 8.0);
      },
      0, 20, 0, 20, 40, 40);
}

FinishParams small_params() {
  FinishParams p;
  p.tool = Cutter::ball(2);
  p.stepover_mm = 0.5;
  p.step_down_mm = 0.5;
  p.chord_tolerance_mm = 0.005;
  p.safe_z_mm = 15;
  return p;
}

std::vector<gcode::Move> moves(const gcode::Program& prog) {
  std::vector<gcode::Move> out;
  for (const auto& it : prog.items)
    if (const auto* m = std::get_if<gcode::Move>(&it)) out.push_back(*m);
  return out;
}

/// Every feed move, sampled every 0.05 mm, stays above the brute-force drop-cutter: by at most
/// tol::chord_below_mm measured vertically, or, with `along_normal`, measured along the CL
/// surface's normal (a Z-level path's tolerance is horizontal, so on a steep wall its vertical dip
/// is the normal one over cos(slope)).
void expect_no_gouge(const ingest::Mesh& mesh, const Cutter& c, const FinishPlan& plan, double z_shift,
                     bool along_normal = false, const DropCutter* indexed = nullptr,
                     std::array<double, 4> window = {-1e300, 1e300, -1e300, 1e300}) {
  // The brute-force oracle, or for a large mesh the indexed drop-cutter (checked against it by
  // DropCutter.RandomMeshesMatchBruteForce).
  auto drop = [&](double x, double y) { return indexed ? indexed->drop(x, y) : drop_brute_force(mesh, c, x, y); };
  gcode::Point3 at{0, 0, 0};
  double worst = -1e9;
  std::size_t checked = 0, index = 0;
  std::string where;
  for (const auto& m : moves(plan.program)) {
    ++index;
    if (m.motion == gcode::Motion::Line) {
      const double len = std::hypot(m.to[0] - at[0], m.to[1] - at[1]);
      const int n = std::max(1, static_cast<int>(std::ceil(len / 0.05)));
      for (int k = 1; k <= n; k += (n > 8 ? 3 : 1)) {
        const double t = static_cast<double>(k) / n;
        const double x = at[0] + t * (m.to[0] - at[0]), y = at[1] + t * (m.to[1] - at[1]);
        const double z = at[2] + t * (m.to[2] - at[2]) - z_shift;
        if (x < window[0] || x > window[1] || y < window[2] || y > window[3]) continue;
        const CLPoint cl = drop(x, y);
        double dip = cl.z - z;
        if (along_normal && dip > tol::chord_below_mm) {
          const double e = 0.005;
          const double gx = (drop(x + e, y).z - drop(x - e, y).z) / (2 * e);
          const double gy = (drop(x, y + e).z - drop(x, y - e).z) / (2 * e);
          dip /= std::sqrt(1 + gx * gx + gy * gy);
        }
        if (cl.contact != Contact::None && dip > worst) {
          worst = dip;
          where = "move " + std::to_string(index) + " at (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                  std::to_string(z) + ")";
        }
        ++checked;
      }
    }
    at = m.to;
  }
  EXPECT_GT(checked, 100u);
  EXPECT_LE(worst, tol::chord_below_mm + 1e-9) << "the path dips below the drop-cutter surface, worst at " << where;
}

TEST(FinishStrategy, ParseAndNames) {
  EXPECT_EQ(parse_strategy("4"), Strategy::Waterline);
  EXPECT_THROW((void)parse_strategy("6"), Error);
  EXPECT_THROW((void)parse_strategy("raster"), Error);
  EXPECT_EQ(strategy_name(Strategy::Raster), "2 3D finishing (parallel)");
  EXPECT_EQ(all_strategies().size(), 5u);
}

TEST(FinishStrategy, RejectsBadParameters) {
  const auto mesh = box(0, 0, 0, 20, 10, 5);
  const DropCutter dc(mesh, Cutter::ball(2));
  auto p = small_params();
  p.stepover_mm = 0;
  EXPECT_THROW((void)plan_finish(mesh, dc, Strategy::Raster, p), Error);
  p = small_params();
  p.step_down_mm = 0;
  EXPECT_THROW((void)plan_finish(mesh, dc, Strategy::Waterline, p), Error);
  p = small_params();
  p.safe_z_mm = 3;  // below the part top
  EXPECT_THROW((void)plan_finish(mesh, dc, Strategy::Raster, p), Error);
  const auto tiny = box(0, 0, 0, 1.5, 1.5, 1);  // smaller than the Ø2 tool
  const DropCutter dt(tiny, Cutter::ball(2));
  EXPECT_THROW((void)plan_finish(tiny, dt, Strategy::Raster, small_params()), Error);
}

TEST(FinishStrategy, RasterOnAFlatTopIsOnePassPerStepoverAtTheTopWithNoLift) {
  const auto mesh = box(0, 0, 0, 20, 10, 5);
  const DropCutter dc(mesh, Cutter::ball(2));
  auto p = small_params();
  p.stepover_mm = 0.2;
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::Raster, p);
  ASSERT_EQ(plan.passes.size(), 51u);  // y = 0, 0.2, …, 10
  for (std::size_t k = 0; k < plan.passes.size(); ++k) {
    const auto& pts = plan.passes[k].points;
    ASSERT_EQ(pts.size(), 2u) << "a flat pass simplifies to its two ends";
    EXPECT_NEAR(pts[0].y(), 0.2 * static_cast<double>(k), 1e-9);
    EXPECT_NEAR(std::abs(pts[1].x() - pts[0].x()), 20, 1e-9);
    for (const auto& q : pts) EXPECT_NEAR(q.z(), 5, 1e-9);
  }
  EXPECT_EQ(plan.lifts, 0u);
  EXPECT_NEAR(plan.path_length_mm, 51 * 20 + 50 * 0.2 + 1 /* plunge */, 1e-6);
  expect_no_gouge(mesh, Cutter::ball(2), plan, 0);
}

TEST(FinishStrategy, RasterFollowsTheDropCutterOnAFreeForm) {
  const auto mesh = solid([](double x, double y) { return 3 + std::sin(x / 3) * std::cos(y / 4) + 0.02 * x * y; }, 0,
                          20, 0, 16, 60, 48);
  for (const Cutter c : {Cutter::ball(2), Cutter::flat(3), Cutter::bull(4, 0.5)}) {
    const DropCutter dc(mesh, c);
    auto p = small_params();
    p.tool = c;
    p.raster_angle_deg = 30;
    p.z_shift = -12;
    p.safe_z_mm = 5;
    const FinishPlan plan = plan_finish(mesh, dc, Strategy::Raster, p);
    EXPECT_EQ(plan.lifts, 0u) << c.describe();
    // Every pass runs at 30° to X.
    for (const auto& pass : plan.passes) {
      const Eigen::Vector2d d = (pass.points.back() - pass.points.front()).head<2>();
      if (d.norm() > 1) {
        EXPECT_NEAR(std::abs(std::atan2(d.y(), d.x()) * 180 / std::numbers::pi), d.x() > 0 ? 30 : 150, 1e-6);
      }
    }
    expect_no_gouge(mesh, c, plan, p.z_shift);
  }
}

TEST(FinishStrategy, WaterlinePointsLieOnTheirLevelWithinTheTolerance) {
  const auto mesh = pyramid();
  const Cutter c = Cutter::ball(2);
  const DropCutter dc(mesh, c);
  auto p = small_params();
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::Waterline, p);
  ASSERT_FALSE(plan.passes.empty());
  std::size_t checked = 0;
  for (const auto& pass : plan.passes) {
    for (const auto& q : pass.points) {
      // Air side: the cutter at this level does not cut in …
      EXPECT_LE(dc.drop(q.x(), q.y()).z, q.z() + 1e-9);
      // … and the part is within the tolerance towards the centre (the flanks face outwards).
      const Eigen::Vector2d in = Eigen::Vector2d(10, 10) - q.head<2>();
      const Eigen::Vector2d step = in.normalized() * (p.chord_tolerance_mm * 1.5);
      const auto cl = dc.drop(q.x() + step.x(), q.y() + step.y());
      if (q.z() > 0.5 + c.radius() + 0.01) {  // above the shelf the level is on the flank
        EXPECT_GE(cl.z, q.z() - 1e-9) << "at " << q.transpose();
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 200u);
  // Levels are step-down apart, top-down, and each closed around the pyramid.
  EXPECT_TRUE(plan.passes.front().closed);
  EXPECT_GE(plan.passes.front().points.front().z(), plan.passes.back().points.front().z());
  expect_no_gouge(mesh, c, plan, 0);
}

TEST(FinishStrategy, WaterlineLoopsClimbMillAroundTheMaterial) {
  const auto mesh = pyramid();
  const DropCutter dc(mesh, Cutter::ball(2));
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::Waterline, small_params());
  for (const auto& pass : plan.passes) {
    if (!pass.closed) continue;
    double area2 = 0;  // shoelace: < 0 ⇒ clockwise ⇒ material (inside) on the right
    for (std::size_t i = 0; i + 1 < pass.points.size(); ++i)
      area2 += pass.points[i].x() * pass.points[i + 1].y() - pass.points[i + 1].x() * pass.points[i].y();
    EXPECT_LT(area2, 0);
  }
}

TEST(FinishStrategy, ScallopModeSpacesPassesByTheThreeDimensionalStepover) {
  const double slope = 30 * std::numbers::pi / 180;
  const auto mesh = solid([&](double x, double) { return 1 + x * std::tan(slope); }, 0, 10, 0, 10, 10, 10);
  const Cutter c = Cutter::ball(2);
  const DropCutter dc(mesh, c);
  auto p = small_params();
  p.raster_angle_deg = 90;  // passes along Y: the slope runs across them
  p.scallop_mm = 0.005;
  p.safe_z_mm = 20;
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::ScallopMode, p);
  const double d3 = 2 * std::sqrt(p.scallop_mm * (2 * c.radius() - p.scallop_mm));  // 3D stepover on a plane
  std::vector<double> xs;
  for (const auto& pass : plan.passes) xs.push_back(pass.points.front().x());
  std::sort(xs.begin(), xs.end());
  std::size_t interior = 0;
  for (std::size_t i = 1; i < xs.size(); ++i) {
    const double dx = xs[i] - xs[i - 1];
    if (xs[i - 1] < 1.5 || xs[i] > 8.5) continue;  // away from the walls
    EXPECT_LE(dx / std::cos(slope), d3 * (1 + 1e-6));
    EXPECT_GE(dx / std::cos(slope), d3 * 0.95);
    ++interior;
  }
  EXPECT_GT(interior, 30u);
  expect_no_gouge(mesh, c, plan, 0);
}

TEST(FinishStrategy, EquidistantLoopsOnAFlatTopAreStepoverMultiplesFromTheBoundary) {
  const auto mesh = box(0, 0, 0, 20, 12, 5);
  const DropCutter dc(mesh, Cutter::ball(2));
  auto p = small_params();
  p.stepover_mm = 0.4;
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::Equidistant, p);
  ASSERT_GT(plan.passes.size(), 10u);
  std::size_t checked = 0;
  for (const auto& pass : plan.passes) {
    EXPECT_TRUE(pass.closed);
    for (std::size_t i = 0; i + 1 < pass.points.size(); ++i) {
      const Eigen::Vector3d q = 0.5 * (pass.points[i] + pass.points[i + 1]);  // mid-segment
      const double dx = std::min(q.x(), 20 - q.x()), dy = std::min(q.y(), 12 - q.y());
      if (std::abs(dx - dy) < 1.0) continue;  // near the diagonals first-order marching is not exact
      const double d = std::min(dx, dy);
      const double k = std::round(d / p.stepover_mm);
      // First-order marching carries the corners' error a little along the edges (~5e-5 mm here).
      EXPECT_NEAR(d, k * p.stepover_mm, 1e-3) << q.transpose();
      EXPECT_NEAR(q.z(), 5, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20u);
  expect_no_gouge(mesh, Cutter::ball(2), plan, 0);
}

TEST(FinishStrategy, SlopeModeRastersTheShallowAndContoursTheSteep) {
  const auto mesh = pyramid();
  const DropCutter dc(mesh, Cutter::ball(2));
  auto p = small_params();
  p.boundary_angle_deg = 30;
  const FinishPlan plan = plan_finish(mesh, dc, Strategy::SlopeMode, p);
  const FinishPlan raster = plan_finish(mesh, dc, Strategy::Raster, p);
  const FinishPlan water = plan_finish(mesh, dc, Strategy::Waterline, p);
  std::size_t flat_level = 0, sloped_level = 0;
  for (const auto& pass : plan.passes) {
    const bool level = std::all_of(pass.points.begin(), pass.points.end(),
                                   [&](const auto& q) { return std::abs(q.z() - pass.points.front().z()) < 1e-12; });
    // Constant-Z pieces lie on the 45° flanks (between the shelf and the plateau).
    if (level && pass.points.size() > 2) {
      for (const auto& q : pass.points) {
        const double r = std::max(std::abs(q.x() - 10), std::abs(q.y() - 10));
        EXPECT_GT(r, 2.0) << "a Z-level piece on the plateau";
      }
      ++sloped_level;
    } else {
      ++flat_level;
    }
  }
  EXPECT_GT(sloped_level, 0u);
  EXPECT_GT(flat_level, 0u);
  // Less Z-level work than the full waterline, less raster than the full raster.
  EXPECT_LT(plan.path_length_mm, raster.path_length_mm + water.path_length_mm);
  expect_no_gouge(mesh, Cutter::ball(2), plan, 0);
}

TEST(FinishStrategy, SamePathWithOneOrTwoThreads) {
  const auto mesh = pyramid();
  const DropCutter dc(mesh, Cutter::bull(3, 0.5));
  auto p = small_params();
  p.tool = Cutter::bull(3, 0.5);
  for (const Strategy s : all_strategies()) {
    omp_set_num_threads(1);
    const FinishPlan a = plan_finish(mesh, dc, s, p);
    omp_set_num_threads(2);
    const FinishPlan b = plan_finish(mesh, dc, s, p);
    const auto ma = moves(a.program), mb = moves(b.program);
    ASSERT_EQ(ma.size(), mb.size()) << strategy_name(s);
    for (std::size_t i = 0; i < ma.size(); ++i) {
      ASSERT_EQ(ma[i].to, mb[i].to) << strategy_name(s) << " move " << i;
      ASSERT_EQ(ma[i].motion, mb[i].motion);
    }
  }
}

TEST(FinishStrategy, PlanningSeveralTogetherEqualsPlanningEachAlone) {
  // Shared pieces (raster lines, Z-level loops) are computed once and must not change a plan.
  const auto mesh = pyramid();
  const DropCutter dc(mesh, Cutter::ball(2));
  const auto p = small_params();
  const std::vector<Strategy> order{Strategy::Waterline, Strategy::SlopeMode, Strategy::Raster, Strategy::Equidistant,
                                    Strategy::ScallopMode};
  const std::vector<FinishPlan> together = plan_finish(mesh, dc, order, p);
  ASSERT_EQ(together.size(), order.size());
  std::size_t drops_together = 0, drops_alone = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const FinishPlan alone = plan_finish(mesh, dc, order[k], p);
    EXPECT_EQ(together[k].strategy, order[k]);
    const auto ma = moves(together[k].program), mb = moves(alone.program);
    ASSERT_EQ(ma.size(), mb.size()) << strategy_name(order[k]);
    for (std::size_t i = 0; i < ma.size(); ++i)
      ASSERT_EQ(ma[i].to, mb[i].to) << strategy_name(order[k]) << " move " << i;
    EXPECT_EQ(together[k].lifts, alone.lifts);
    // What the strategy needs does not depend on what was planned with it (MPI plans alone).
    EXPECT_EQ(together[k].drops_needed, alone.drops) << strategy_name(order[k]);
    EXPECT_EQ(alone.drops_needed, alone.drops) << strategy_name(order[k]);
    drops_together += together[k].drops;
    drops_alone += alone.drops;
  }
  // Slope mode after the waterline and before the raster: its Z-levels come free, its raster is
  // charged to it and comes free to the raster.
  EXPECT_LT(together[1].drops, plan_finish(mesh, dc, Strategy::SlopeMode, p).drops);
  EXPECT_LT(drops_together, drops_alone);
}

TEST(FinishStrategy, NarrowRidgesAndSteepWallsNeverGouge) {
  // Regression (held-out parts s3 and s4 of the default run): ridges about as narrow as the
  // cutter, a steep round boss and a slanted crest. A waterline chord's split point once came from
  // a far probe on another branch of the level (0.19 mm into s3), and a raster interval that
  // climbs a wall's edge could hide the CL above its chord off the midpoint (0.012 mm into s4).
  const auto mesh = solid(
      [](double x, double y) {
        double z = 1 + 2.5 * std::exp(-(x - 6) * (x - 6) / 0.4) * (1 + 0.4 * std::sin(1.3 * y));
        z += 2 * std::exp(-(y - 13 + 0.35 * x) * (y - 13 + 0.35 * x) / 0.3);
        const double r = std::hypot(x - 14, y - 6);
        z += 3 / (1 + std::exp((r - 3) * 12));  // a boss with a steep, rounded wall
        return z;
      },
      0, 20, 0, 20, 40, 40);
  const DropCutter dc(mesh, Cutter::ball(2));
  auto p = small_params();
  p.stepover_mm = 0.4;
  p.step_down_mm = 0.25;
  for (const FinishPlan& plan : plan_finish(mesh, dc, std::vector{Strategy::Waterline, Strategy::Raster}, p)) {
    SCOPED_TRACE(strategy_name(plan.strategy));
    expect_no_gouge(mesh, Cutter::ball(2), plan, 0, plan.strategy == Strategy::Waterline);
  }
}

TEST(FinishStrategy, WaterlineRidesOverASliverItsSplitsCannotFollow) {
  // Regression (default training part s3_varying_curvature_06, strategy 4, level Z −1.2001 of the
  // program): a sliver of the level set a hair above the level, crossed back and forth by the 64
  // splits of one chord; the last sub-chord cut 0.0052 mm into the part at (5.79, 52.03).
  // The part as `millnet dataset` writes it (binary STL, float vertices) and every command reads it.
  const std::filesystem::path stl = std::filesystem::temp_directory_path() / "millnet_test_s3_varying_curvature_06.stl";
  ingest::save_stl_binary(datasets::make_part(datasets::Family::VaryingCurvature, 5, 7).mesh, stl);
  const auto mesh = ingest::load_prepared(stl, {});
  std::filesystem::remove(stl);
  const DropCutter dc(mesh, Cutter::ball(2));
  FinishParams p = small_params();  // at the default run's p_f and a_a
  p.stepover_mm = 0.2;
  p.step_down_mm = 0.04;
  p.safe_z_mm = 5;
  p.z_shift = -(mesh.V.col(2).maxCoeff() + 1);  // the program frame: Z 0 = part top + 1 mm
  const std::vector<FinishPlan> plans = plan_finish(mesh, dc, std::vector{Strategy::Waterline}, p);
  ASSERT_EQ(plans.size(), 1u);
  // The whole part (a crop would move the contour grid and the levels), checked around the sliver.
  expect_no_gouge(mesh, p.tool, plans[0], p.z_shift, true, &dc, {3.3, 8.3, 49.5, 54.5});
}

}  // namespace
}  // namespace millnet::finish
