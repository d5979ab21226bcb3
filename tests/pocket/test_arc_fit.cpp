// Arc fitting (pocket/src/arc_fit.hpp): chorded circles become exact arcs, everything else stays as it
// was, nothing moves by more than the tolerance, and the walls' clearance is never given up.
#include "arc_fit.hpp"

#include "millnet/pocket/tolerances.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace millnet::pocket;

namespace {

/// n + 1 points on the circle (c, r) from angle a0 to a1 (radians), bulges 0.
std::vector<Vertex> chorded(const Vec2& c, double r, double a0, double a1, int n) {
  std::vector<Vertex> v;
  for (int k = 0; k <= n; ++k) {
    const double t = a0 + (a1 - a0) * k / n;
    v.push_back({c.x() + r * std::cos(t), c.y() + r * std::sin(t), 0.0});
  }
  return v;
}

/// Largest distance from points sampled every 0.01 mm along `fitted` to the polyline `input`
/// (brute force): the fitted path must stay within the tolerance of what it replaces.
double deviation(const std::vector<Vertex>& fitted, const std::vector<Vertex>& input) {
  double worst = 0;
  for (std::size_t k = 0; k + 1 < fitted.size(); ++k) {
    const Segment s{fitted[k].p(), fitted[k + 1].p(), fitted[k].bulge};
    const int n = std::max(1, static_cast<int>(std::ceil(length(s) / 0.01)));
    for (int i = 0; i <= n; ++i) {
      const Vec2 p = point_at(s, static_cast<double>(i) / n);
      double best = 1e300;
      for (std::size_t j = 0; j + 1 < input.size(); ++j)
        best = std::min(best, distance(Segment{input[j].p(), input[j + 1].p(), 0.0}, p));
      worst = std::max(worst, best);
    }
  }
  return worst;
}

}  // namespace

TEST(ArcFit, AChordedArcBecomesOneExactArc) {
  const Vec2 c(3, 4);
  const double r = 7, a0 = 0.3, a1 = 0.3 + 150 * M_PI / 180;
  const auto in = chorded(c, r, a0, a1, 60);  // 2.5° chords: sagitta 1.7 µm ≤ 2 µm
  const auto out = fit_arcs(in, tol::arc_fit_mm, nullptr);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].bulge, std::tan((a1 - a0) / 4), 1e-12);  // CCW: positive
  const Arc arc = arc_of(Segment{out[0].p(), out[1].p(), out[0].bulge});
  EXPECT_NEAR(arc.center.x(), 3, 1e-9);
  EXPECT_NEAR(arc.center.y(), 4, 1e-9);
  EXPECT_NEAR(arc.radius, 7, 1e-9);
  EXPECT_EQ(out[1].x, in.back().x);  // the ends are the input's own
  EXPECT_LE(deviation(out, in), tol::arc_fit_mm + 1e-9);
}

TEST(ArcFit, AClockwiseRunGetsANegativeBulge) {
  const auto in = chorded(Vec2(0, 0), 5, 1.0, 0.2, 40);
  const auto out = fit_arcs(in, tol::arc_fit_mm, nullptr);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].bulge, std::tan(-0.8 / 4), 1e-12);
}

TEST(ArcFit, AFullCircleIsCutIntoArcsOfLessThanAHalfTurnThatCloseOnItself) {
  const auto in = chorded(Vec2(10, -2), 12, 0, 2 * M_PI, 200);
  const auto out = fit_arcs(in, tol::arc_fit_mm, nullptr);
  EXPECT_LE(out.size(), 5u);
  std::size_t arcs = 0;
  double len = 0;
  for (std::size_t k = 0; k + 1 < out.size(); ++k) {
    EXPECT_LT(std::abs(out[k].bulge), 1.0);
    arcs += out[k].bulge != 0.0;
    len += length(Segment{out[k].p(), out[k + 1].p(), out[k].bulge});
  }
  EXPECT_GE(arcs, 2u);
  EXPECT_NEAR(out.back().x, in.back().x, 0);
  EXPECT_NEAR(len, 2 * M_PI * 12, 0.01);  // the polygon's own length is 0.006 mm shorter
  EXPECT_LE(deviation(out, in), tol::arc_fit_mm + 1e-9);
}

TEST(ArcFit, StraightRunsCornersAndCoarsePolygonsStayAsTheyAre) {
  // A square path with 1 mm steps: collinear runs and 90° corners are no circle.
  std::vector<Vertex> square;
  for (int k = 0; k < 10; ++k) square.push_back({static_cast<double>(k), 0, 0});
  for (int k = 0; k <= 10; ++k) square.push_back({10, static_cast<double>(k), 0});
  const auto sq = fit_arcs(square, tol::arc_fit_mm, nullptr);
  ASSERT_EQ(sq.size(), square.size());
  for (const Vertex& v : sq) EXPECT_EQ(v.bulge, 0.0);
  // A regular octagon's vertices lie on a circle, but its chords are 0.76 mm from it: no arc.
  const auto oct = chorded(Vec2(0, 0), 10, 0, 2 * M_PI, 8);
  for (const Vertex& v : fit_arcs(oct, tol::arc_fit_mm, nullptr)) EXPECT_EQ(v.bulge, 0.0);
  // Points 0.01 mm off their circle (five times the tolerance) are no arc either.
  auto noisy = chorded(Vec2(0, 0), 10, 0, 1.5, 60);
  for (std::size_t k = 0; k < noisy.size(); ++k) noisy[k].x += (k % 2 ? 0.01 : -0.01);
  for (const Vertex& v : fit_arcs(noisy, tol::arc_fit_mm, nullptr)) EXPECT_EQ(v.bulge, 0.0);
}

TEST(ArcFit, ExistingArcsAndTheLinesAroundARunAreKept) {
  std::vector<Vertex> in{{-5, 0, 0}, {-1, 0, 0}};
  for (const Vertex& v : chorded(Vec2(0, 1), 1, -M_PI / 2, 0.5, 30)) in.push_back(v);  // from (0, 0)
  in.back().bulge = 0.4;  // then an existing arc to the last vertex
  in.push_back({-3, 6, 0});
  const auto out = fit_arcs(in, tol::arc_fit_mm, nullptr);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out[0].bulge, 0.0);
  EXPECT_EQ(out[1].bulge, 0.0);  // the line (−1, 0) → (0, 0) is tangent, not on the circle's run
  EXPECT_GT(out[2].bulge, 0.0);
  EXPECT_EQ(out[3].bulge, 0.4);
  EXPECT_EQ(out[4].x, -3);
}

TEST(ArcFit, AnArcThatWouldCutIntoTheClearanceIsRefused) {
  // A Ø20 island in a big square; clearance 5 ⇒ tool centres at ≥ 15 from the island's centre.
  Region reg;
  reg.boundary = {{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}};
  reg.islands.push_back({{-10, 0, -1}, {10, 0, -1}});
  const Clearance walls(reg, 5.0);
  const auto safe = chorded(Vec2(0, 0), 15.0005, 0.2, 2.0, 80);
  const auto inside = chorded(Vec2(0, 0), 14.999, 0.2, 2.0, 80);  // 1 µm into the clearance
  EXPECT_EQ(fit_arcs(safe, tol::arc_fit_mm, &walls).size(), 2u);
  EXPECT_EQ(fit_arcs(inside, tol::arc_fit_mm, nullptr).size(), 2u);
  for (const Vertex& v : fit_arcs(inside, tol::arc_fit_mm, &walls)) EXPECT_EQ(v.bulge, 0.0);
}
