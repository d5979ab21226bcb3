// job/tool_choice: the concave radius read off a mesh against analytic surfaces (a faceted trough of
// radius R gives R exactly; a ridge, a V-groove and a plane give none; a short tight radius under
// kRestShare of the edge length is left to rest machining), and the finishing ball picked from a
// library by the part's size, that radius and the depth its stick-out must reach.
#include "millnet/job/tool_choice.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

using namespace millnet;

namespace {

/// The surface z = profile(s), s along X at the given stations, extruded along Y over [0, length]
/// in `rows` rows, as a triangle grid (normals up).
ingest::Mesh extruded(const std::vector<std::array<double, 2>>& xz, double length, int rows) {
  const int n = static_cast<int>(xz.size());
  ingest::Mesh m;
  m.V.resize(static_cast<Eigen::Index>(n * (rows + 1)), 3);
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i < n; ++i) {
      const auto& p = xz[static_cast<std::size_t>(i)];
      m.V.row(j * n + i) << p[0], length * j / rows, p[1];
    }
  m.F.resize(static_cast<Eigen::Index>(2 * (n - 1) * rows), 3);
  Eigen::Index f = 0;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

/// A circular profile of radius r about (0, r) (a trough, concave) or (0, −r) (a ridge), from −deg
/// to +deg in `steps` facets.
std::vector<std::array<double, 2>> arc(double r, double deg, int steps, bool trough) {
  std::vector<std::array<double, 2>> p;
  for (int k = 0; k <= steps; ++k) {
    const double a = (-deg + 2 * deg * k / steps) * std::numbers::pi / 180;
    p.push_back({r * std::sin(a), trough ? r - r * std::cos(a) : r * std::cos(a) - r});
  }
  return p;
}

tooling::Tool ball(const char* id, double d, double stickout) {
  tooling::Tool t;
  t.id = id;
  t.type = tooling::ToolType::Ball;
  t.diameter_mm = d;
  t.corner_radius_mm = d / 2;
  t.stickout_mm = stickout;
  return t;
}

std::vector<tooling::Tool> library() {
  tooling::Tool flat = ball("em10", 10, 50);
  flat.type = tooling::ToolType::Flat;
  flat.corner_radius_mm = 0;
  return {flat, ball("bn2", 2, 45), ball("bn6", 6, 35), ball("bn10", 10, 45)};
}

job::PartShape shape(double size, double radius, double depth) {
  job::PartShape s;
  s.size_mm = size;
  s.concave_radius_mm = radius;
  s.depth_mm = depth;
  return s;
}

}  // namespace

TEST(ToolChoice, AFacetedTroughGivesItsRadiusAndARidgeNone) {
  for (const double r : {0.8, 4.0, 25.0}) {
    const job::PartShape trough = job::part_shape(extruded(arc(r, 60, 24, true), 20, 5), 30);
    EXPECT_NEAR(trough.concave_radius_mm, r, 1e-9 * r) << r;  // facets of one circle: exact
    EXPECT_NEAR(trough.concave_edges_mm, 23 * 20, 1e-9);      // the 23 inner generators, 20 mm each
    EXPECT_NEAR(trough.depth_mm, 30, 1e-12);                  // its lowest point is at z 0
    EXPECT_NEAR(trough.size_mm, std::max(20.0, 2 * r * std::sin(std::numbers::pi / 3)), 1e-9);  // the longer side
    const job::PartShape ridge = job::part_shape(extruded(arc(r, 60, 24, false), 20, 5), 30);
    EXPECT_TRUE(std::isinf(ridge.concave_radius_mm)) << r;
    EXPECT_EQ(ridge.concave_edges_mm, 0);
  }
}

TEST(ToolChoice, SharpCornersAndPlanesDoNotBoundTheBall) {
  // A V-groove (faces turning by 90°) and a plane: no concave radius to respect.
  const job::PartShape groove = job::part_shape(extruded({{-10, 10}, {0, 0}, {10, 10}}, 20, 4), 12);
  EXPECT_TRUE(std::isinf(groove.concave_radius_mm));
  const job::PartShape plane = job::part_shape(extruded({{-10, 0}, {0, 0}, {10, 0}}, 20, 4), 12);
  EXPECT_TRUE(std::isinf(plane.concave_radius_mm));
  // Turned upside down (every face facing down): not machined from above, nothing measured.
  ingest::Mesh under = extruded(arc(4, 60, 24, true), 20, 5);
  under.F.col(1).swap(under.F.col(2));
  EXPECT_TRUE(std::isinf(job::part_shape(under, 30).concave_radius_mm));
}

TEST(ToolChoice, ATightRadiusOnLessThanTheRestShareIsLeftToRestMachining) {
  // A 10 mm trough 400 mm long beside a 1 mm one 2 mm long: the tight one has 0.03 % of the concave
  // edge length (< kRestShare) and does not decide the ball; 40 mm long (5 %) it does.
  auto two = [](double tight_length) {
    ingest::Mesh a = extruded(arc(10, 60, 24, true), 400, 4);
    ingest::Mesh b = extruded(arc(1, 60, 24, true), tight_length, 1);
    const Eigen::Index na = a.V.rows(), fa = a.F.rows();
    ingest::Mesh m;
    m.V.resize(na + b.V.rows(), 3);
    m.V << a.V, (b.V.rowwise() + Eigen::RowVector3d(50, 0, 0));
    m.F.resize(fa + b.F.rows(), 3);
    m.F << a.F, (b.F.array() + static_cast<std::int32_t>(na)).matrix();
    return job::part_shape(m, 20);
  };
  EXPECT_NEAR(two(2).concave_radius_mm, 10, 1e-9);
  EXPECT_NEAR(two(40).concave_radius_mm, 1, 1e-9);
}

TEST(ToolChoice, TheBallIsTheLargestThePartsSizeAndConcaveRadiusAllowThatReaches) {
  const std::vector<tooling::Tool> lib = library();
  const double inf = std::numeric_limits<double>::infinity();
  auto pick = [&](double size, double radius, double depth) {
    const tooling::Tool* t = job::finishing_ball(lib, shape(size, radius, depth));
    return t == nullptr ? std::string("none") : t->id;
  };
  EXPECT_EQ(pick(300, inf, 20), "bn10");  // a 300 mm part: up to Ø20, the library's largest
  EXPECT_EQ(pick(100, inf, 20), "bn6");   // 100 / 15 = Ø6.7
  EXPECT_EQ(pick(89, inf, 20), "bn2");    // 89 / 15 = Ø5.9
  EXPECT_EQ(pick(300, 4.0, 20), "bn6");   // a 4 mm concave radius admits Ø8
  EXPECT_EQ(pick(300, 1.5, 20), "bn2");   // Ø3
  EXPECT_EQ(pick(300, 4.0, 40), "bn2");   // Ø6's 35 mm stick-out does not reach 40 mm
  EXPECT_EQ(pick(300, 0.2, 20), "bn2");   // nothing that small: the smallest that reaches
  EXPECT_EQ(pick(300, 0.2, 40), "bn2");
  EXPECT_EQ(pick(300, 6.0, 50), "bn2");  // none reaches: the longest stick-out (the holder check refuses)
  EXPECT_EQ(job::finishing_ball({lib[0]}, shape(300, inf, 20)), nullptr);  // no ball at all
}
