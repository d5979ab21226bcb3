// Machining boundaries (issue 38): on an open surface the tool axis stays over the surface (no pass
// drops off its edge to the floor); polygons with islands and a Z range cut the passes on their own
// segments, at the crossings (hand-computed), and a link never crosses what is left out. Oracles:
// brute-force point-in-triangle over every face, the analytic plane.
#include "millnet/core/error.hpp"
#include "millnet/finish/strategy.hpp"

#include "ingest/builders.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <variant>
#include <vector>

namespace millnet::finish {
namespace {

using tooling::Cutter;

FinishParams params() {
  FinishParams p;
  p.tool = Cutter::ball(2);
  p.stepover_mm = 0.5;
  p.step_down_mm = 0.5;
  p.chord_tolerance_mm = 0.005;
  p.safe_z_mm = 20;
  return p;
}

/// The dome z = 10 − (x² + y²)/80 as an open surface: the faces of a 1 mm grid over [−16, 16]²
/// whose centroid lies within 15 mm of the axis (a jagged disc, no walls, no base).
ingest::Mesh open_dome() {
  const ingest::Mesh grid =
      testing_ingest::surface([](double x, double y) { return 10 - (x * x + y * y) / 80; }, -16, 16, -16, 16, 32, 32);
  ingest::Mesh m;
  m.V = grid.V;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index f = 0; f < grid.F.rows(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += grid.V.row(grid.F(f, k)).transpose() / 3;
    if (c.head<2>().norm() < 15) keep.push_back(f);
  }
  m.F.resize(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = grid.F.row(keep[i]);
  return m;
}

/// Brute force: whether the XY projection of some face contains (x, y) within `tol`.
bool over_mesh(const ingest::Mesh& m, double x, double y, double tol = 1e-4) {
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector2d a = m.V.row(m.F(f, 0)).head<2>(), b = m.V.row(m.F(f, 1)).head<2>(),
                          c = m.V.row(m.F(f, 2)).head<2>();
    auto side = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
      const Eigen::Vector2d d = q - p;
      return (d.x() * (y - p.y()) - d.y() * (x - p.x())) / d.norm();
    };
    const double s = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x() > 0 ? 1 : -1;
    if (s * side(a, b) >= -tol && s * side(b, c) >= -tol && s * side(c, a) >= -tol) return true;
  }
  return false;
}

/// Every feed move of the program sampled every `step` mm (mesh frame: z − z_shift), ends included.
void each_feed_point(const FinishPlan& plan, double z_shift, double step,
                     const std::function<void(const Eigen::Vector3d&)>& visit) {
  gcode::Point3 at{0, 0, 0};
  for (const gcode::Item& item : plan.program.items) {
    const auto* m = std::get_if<gcode::Move>(&item);
    if (m == nullptr) continue;
    if (m->motion == gcode::Motion::Line) {
      const double len = std::hypot(m->to[0] - at[0], m->to[1] - at[1]);
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        visit(
            {at[0] + t * (m->to[0] - at[0]), at[1] + t * (m->to[1] - at[1]), at[2] + t * (m->to[2] - at[2]) - z_shift});
      }
    }
    at = m->to;
  }
}

TEST(FinishBoundary, AnOpenSurfaceIsFinishedWithoutLeavingIt) {
  const ingest::Mesh dome = open_dome();
  FinishParams p = params();
  const DropCutter dropper(dome, p.tool);
  for (const Strategy st : {Strategy::Raster, Strategy::Waterline}) {
    const FinishPlan plan = plan_finish(dome, dropper, st, p);
    std::size_t points = 0, off = 0;
    double lowest = 1e9;
    each_feed_point(plan, p.z_shift, 0.25, [&](const Eigen::Vector3d& q) {
      ++points;
      off += over_mesh(dome, q.x(), q.y()) ? 0U : 1U;
      lowest = std::min(lowest, q.z());
    });
    EXPECT_GT(points, 1000u) << strategy_name(st);
    EXPECT_EQ(off, 0u) << strategy_name(st) << ": feed points off the surface";
    // The dome's edge is at r ≤ 16: z ≥ 10 − 256/80 = 6.8; the floor (the lowest vertex) is not visited.
    EXPECT_GT(lowest, 6.7) << strategy_name(st);
  }
  // The raster covers the surface: about its area / p_f of passes (π·15² / 0.5 = 1414 mm).
  const FinishPlan raster = plan_finish(dome, dropper, Strategy::Raster, p);
  EXPECT_GT(raster.path_length_mm, 1300);
  // The old box (the footprint, the table under it): the raster drops off the edge.
  p.boundary.on_part = false;
  const FinishPlan boxed = plan_finish(dome, dropper, Strategy::Raster, p);
  std::size_t off = 0;
  each_feed_point(boxed, p.z_shift, 0.25,
                  [&](const Eigen::Vector3d& q) { off += over_mesh(dome, q.x(), q.y()) ? 0U : 1U; });
  EXPECT_GT(off, 100u);
}

TEST(FinishBoundary, PolygonsIslandsAndAZRangeCutPassesAtTheirCrossings) {
  // The plane z = x/4 on a 40 × 40 block; a Ø2 ball's tip rides R(1/cos θ − 1) above it, tan θ = 1/4.
  const ingest::Mesh ramp = testing_ingest::solid([](double x, double) { return 2 + x / 4; }, 0, 40, 0, 40, 8, 8);
  FinishParams p = params();
  p.boundary.polygons = {{{10, 10}, {30, 10}, {30, 30}, {10, 30}},   // the outline
                         {{18, 18}, {18, 22}, {22, 22}, {22, 18}}};  // an island left out
  const double lift = std::sqrt(1 + 1.0 / 16) - 1;                   // R = 1
  p.boundary.z_min = 2 + 13 / 4.0 + lift;                            // the tip at x = 13 …
  p.boundary.z_max = 2 + 27 / 4.0 + lift;                            // … to x = 27
  const DropCutter dropper(ramp, p.tool);
  const FinishPlan plan = plan_finish(ramp, dropper, Strategy::Raster, p);
  double x_lo = 1e9, x_hi = -1e9, left_of_island = -1e9, right_of_island = 1e9;
  std::size_t points = 0, outside = 0;
  each_feed_point(plan, p.z_shift, 0.05, [&](const Eigen::Vector3d& q) {
    ++points;
    const bool in_outline = q.x() >= 10 - 1e-9 && q.x() <= 30 + 1e-9 && q.y() >= 10 - 1e-9 && q.y() <= 30 + 1e-9;
    const bool in_island = q.x() > 18 + 1e-9 && q.x() < 22 - 1e-9 && q.y() > 18 + 1e-9 && q.y() < 22 - 1e-9;
    const bool in_z = q.z() >= p.boundary.z_min - 1e-6 && q.z() <= p.boundary.z_max + 1e-6;
    outside += in_outline && !in_island && in_z ? 0U : 1U;
    x_lo = std::min(x_lo, q.x());
    x_hi = std::max(x_hi, q.x());
    if (q.y() > 18.5 && q.y() < 21.5) {
      if (q.x() < 20) left_of_island = std::max(left_of_island, q.x());
      if (q.x() > 20) right_of_island = std::min(right_of_island, q.x());
    }
  });
  EXPECT_GT(points, 2000u);
  EXPECT_EQ(outside, 0u) << "feed moves (cuts and links) outside the boundary";
  // The pieces end where the passes cross: at x = 13 and 27 (the Z range) and 18, 22 (the island),
  // to the bisection's 1e-5 mm.
  EXPECT_NEAR(x_lo, 13, 2e-5);
  EXPECT_NEAR(x_hi, 27, 2e-5);
  EXPECT_NEAR(left_of_island, 18, 2e-5);
  EXPECT_NEAR(right_of_island, 22, 2e-5);
  // The link across the island (4 mm, short enough to stay down) lifts instead: one per pass there.
  EXPECT_GE(plan.lifts, 7u);
}

TEST(FinishBoundary, ABoundaryOffThePartOrAnEmptyZRangeIsRefused) {
  const ingest::Mesh block = testing_ingest::box(0, 0, 0, 20, 20, 5);
  FinishParams p = params();
  const DropCutter dropper(block, p.tool);
  p.boundary.polygons = {{{30, 30}, {40, 30}, {40, 40}}};
  EXPECT_THROW((void)plan_finish(block, dropper, Strategy::Raster, p), Error);
  p.boundary.polygons = {{{1, 1}, {2, 2}}};
  EXPECT_THROW((void)plan_finish(block, dropper, Strategy::Raster, p), Error);
  p.boundary.polygons.clear();
  p.boundary.z_min = 3, p.boundary.z_max = 2;
  EXPECT_THROW((void)plan_finish(block, dropper, Strategy::Raster, p), Error);
  p.boundary.z_min = 6, p.boundary.z_max = 7;  // above the top: nothing to finish
  EXPECT_THROW((void)plan_finish(block, dropper, Strategy::Raster, p), Error);
}

}  // namespace
}  // namespace millnet::finish
