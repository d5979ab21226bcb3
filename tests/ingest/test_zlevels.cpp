// Z-level contours: box on a plate (squares), a hemisphere (circles), a pocket (hole), guarantees.
#include "ingest/builders.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/zlevels.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace millnet::ingest;
using namespace millnet::testing_ingest;

namespace {

bool inside(const std::vector<Eigen::Vector2d>& loop, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Eigen::Vector2d &a = loop[i], &b = loop[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

double dist_to_loop(const std::vector<Eigen::Vector2d>& loop, const Eigen::Vector2d& p) {
  double d = 1e300;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Eigen::Vector2d ab = loop[i] - loop[j];
    const double t = std::clamp((p - loop[j]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    d = std::min(d, (loop[j] + t * ab - p).norm());
  }
  return d;
}

// Every material raster point is inside an outer loop, outside its holes, at ≥ R from the loops.
void expect_covers(const HeightField& f, const std::vector<ContourLoop>& loops, double level, double grow) {
  const double R = grow + 0.5 * std::hypot(f.step_x, f.step_y);
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      if (f.at(i, j) < level) continue;
      const Eigen::Vector2d p(f.x0 + j * f.step_x, f.y0 + i * f.step_y);
      int covering = 0;
      for (std::size_t k = 0; k < loops.size(); ++k) {
        if (loops[k].hole) continue;
        bool in = inside(loops[k].pts, p);
        for (const auto& h : loops)
          if (h.hole && h.parent == static_cast<int>(k) && inside(h.pts, p)) in = false;
        if (in) ++covering;
      }
      ASSERT_EQ(covering, 1) << p.transpose();
      for (const auto& l : loops) ASSERT_GE(dist_to_loop(l.pts, p), R - 1e-9) << p.transpose();
    }
}

}  // namespace

TEST(ZLevels, BoxOnPlateGivesOneSquarePerLevel) {
  const Mesh m = append(box(0, 0, 0, 60, 50, 10), box(20, 15, 10, 40, 35, 30));
  const HeightField f = rasterize_top(m, 1.0);
  const double grow = 2.0;
  const double R = grow + 0.5 * std::sqrt(2.0), over = contour_overshoot_mm(f, grow);
  EXPECT_LT(over, 0.7);
  for (double level : {5.0, 10.0, 20.0, 30.0}) {
    const auto loops = material_contours(f, level, grow);
    ASSERT_EQ(loops.size(), 1u) << level;
    EXPECT_FALSE(loops[0].hole);
    EXPECT_GT(signed_area(loops[0].pts), 0);  // CCW
    const bool top = level > 10;
    const double x0 = top ? 20 : 0, x1 = top ? 40 : 60, y0 = top ? 15 : 0, y1 = top ? 35 : 50;
    for (const auto& p : loops[0].pts) {
      // Outside the material rectangle by between R and R + overshoot (corners rounded).
      const double dx = std::max({x0 - p.x(), p.x() - x1, 0.0}), dy = std::max({y0 - p.y(), p.y() - y1, 0.0});
      const double d = std::hypot(dx, dy);
      EXPECT_GE(d, R - 1e-9);
      EXPECT_LE(d, R + over + 1e-9);
    }
    expect_covers(f, loops, level, grow);
  }
  EXPECT_TRUE(material_contours(f, 30.5, grow).empty());
}

TEST(ZLevels, HemisphereGivesCirclesOfTheAnalyticRadius) {
  const double Rs = 25;
  const Mesh m = surface([Rs](double x, double y) { return std::sqrt(std::max(0.0, Rs * Rs - x * x - y * y)); }, -30,
                         30, -30, 30, 240, 240);
  const HeightField f = rasterize_top(m, 0.5);
  const double R = 0.5 * std::hypot(f.step_x, f.step_y), over = contour_overshoot_mm(f, 0);
  for (double level : {5.0, 15.0, 22.0}) {
    const auto loops = material_contours(f, level, 0.0);
    ASSERT_EQ(loops.size(), 1u);
    const double r = std::sqrt(Rs * Rs - level * level);
    // Raster points at the level lie within r; one raster step inside r is certainly at the level
    // (faceting of the 0.25 mm mesh is far below a step), so the contour radius is within
    // [r − step + R, r + R + overshoot].
    for (const auto& p : loops[0].pts) {
      EXPECT_GE(p.norm(), r - 0.5 + R - 1e-9) << level;
      EXPECT_LE(p.norm(), r + R + over + 1e-9) << level;
    }
    EXPECT_GT(signed_area(loops[0].pts), 0);
    expect_covers(f, loops, level, 0.0);
  }
}

TEST(ZLevels, RingHasAHoleOrientedClockwise) {
  // A 40×40 block with a 16×16 pocket through to z = 2 (floor), walls to z = 12.
  const Mesh m = append(append(append(box(0, 0, 0, 40, 40, 2), box(0, 0, 2, 12, 40, 12)),
                               append(box(28, 0, 2, 40, 40, 12), box(12, 0, 2, 28, 12, 12))),
                        box(12, 28, 2, 28, 40, 12));
  const HeightField f = rasterize_top(m, 1.0);
  const auto loops = material_contours(f, 8.0, 0.5);
  ASSERT_EQ(loops.size(), 2u);
  const ContourLoop& outer = loops[0].hole ? loops[1] : loops[0];
  const ContourLoop& hole = loops[0].hole ? loops[0] : loops[1];
  EXPECT_GT(signed_area(outer.pts), 0);
  EXPECT_LT(signed_area(hole.pts), 0);
  EXPECT_EQ(hole.parent, loops[0].hole ? 1 : 0);
  EXPECT_TRUE(inside(hole.pts, {20, 20}));
  expect_covers(f, loops, 8.0, 0.5);
  EXPECT_THROW((void)material_contours(f, 8.0, -1.0), millnet::Error);
  EXPECT_THROW((void)material_contours(HeightField{}, 8.0, 0.0), millnet::Error);
}
