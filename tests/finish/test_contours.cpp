// Iso-contours of a grid field (finish/src/contours.hpp, white-box): the run-skipping IsoField
// traces exactly the plain scan's contours, and a cone's contour is the hand-computed circle.
#include "contours.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {
using millnet::finish::detail::ContourPoint;
using millnet::finish::detail::GridSpec;
using millnet::finish::detail::IsoField;
using millnet::finish::detail::PlaceCrossing;

PlaceCrossing linear(double level) {
  return [level](const Eigen::Vector2d& in, const Eigen::Vector2d& out, double v_in, double v_out, bool) {
    const double t = std::isfinite(v_out) ? (v_in - level) / (v_in - v_out) : 0.0;
    return std::pair<Eigen::Vector2d, double>(in + t * (out - in), 0.0);
  };
}

double signed_area(const std::vector<ContourPoint>& loop) {
  double a = 0;
  for (std::size_t i = 0; i + 1 < loop.size(); ++i)
    a += loop[i].xy.x() * loop[i + 1].xy.y() - loop[i + 1].xy.x() * loop[i].xy.y();
  return 0.5 * a;
}

}  // namespace

TEST(IsoField, SkippingRunsTracesThePlainScansContoursPointForPoint) {
  // Bumps, noise, NaN holes and plateaus (levels equal to node values), over a grid whose width is
  // not a multiple of the run length; levels below, inside and above the field's range.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const GridSpec g = GridSpec::over(-3, 2, 14.3, 11.1, 0.1);
  std::vector<double> v(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny));
  for (int i = 0; i < g.ny; ++i)
    for (int j = 0; j < g.nx; ++j) {
      const Eigen::Vector2d p = g.node(i, j);
      double z = 3 * std::sin(0.7 * p.x()) * std::cos(0.9 * p.y()) + 0.2 * u(rng);
      if (std::abs(p.x() - 5) < 1 && std::abs(p.y() - 6) < 1) z = 1.0;  // a plateau at a level
      if (u(rng) < 0.01) z = std::numeric_limits<double>::quiet_NaN();
      v[static_cast<std::size_t>(i) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(j)] = z;
    }
  const IsoField fast(g, v), plain(g, v, false);
  std::size_t points = 0;
  for (const double level : {-10.0, -2.5, -1.0, 0.0, 0.37, 1.0, 2.9, 10.0}) {
    const auto a = fast.contours(level, linear(level)), b = plain.contours(level, linear(level));
    ASSERT_EQ(a.size(), b.size()) << "level " << level;
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].size(), b[k].size());
      for (std::size_t m = 0; m < a[k].size(); ++m) {
        ASSERT_EQ(a[k][m].xy, b[k][m].xy);
        ASSERT_EQ(a[k][m].on_boundary, b[k][m].on_boundary);
      }
      points += a[k].size();
    }
  }
  EXPECT_GT(points, 1000U);  // the levels in range do cross the field
}

TEST(IsoField, AConesContourIsItsCircleInsideOnTheLeft) {
  // v = 5 − |p − c|: the contour at level 2 is the circle of radius 3 around c; linear
  // interpolation on a 0.05 grid puts every point within the chord sag of the circle (≤ 1e-3).
  const GridSpec g = GridSpec::over(0, 0, 10, 8, 0.05);
  const Eigen::Vector2d c(4.3, 3.9);
  std::vector<double> v(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny));
  for (int i = 0; i < g.ny; ++i)
    for (int j = 0; j < g.nx; ++j)
      v[static_cast<std::size_t>(i) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(j)] =
          5 - (g.node(i, j) - c).norm();
  const auto loops = IsoField(g, v).contours(2.0, linear(2.0));
  ASSERT_EQ(loops.size(), 1U);
  for (const ContourPoint& p : loops[0]) EXPECT_NEAR((p.xy - c).norm(), 3.0, 1e-3);
  EXPECT_NEAR(signed_area(loops[0]), M_PI * 9, 0.02);  // > 0: counter-clockwise around the inside
}
