// Drop-cutter: analytic surfaces against closed-form CL heights, forced contact types on single
// triangles, the bull-nose edge against an independent 1-D search, random meshes against the
// brute-force oracle, no-penetration/touching properties, thread-count invariance.
#include "ingest/builders.hpp"
#include "millnet/core/error.hpp"
#include "millnet/tooling/cutter.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "sampling.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace millnet::finish;
using millnet::ingest::Mesh;
using millnet::testing_ingest::solid;
using millnet::testing_ingest::surface;
using millnet::tooling::Cutter;
using millnet::tooling::CutterType;

namespace {

constexpr double kExact = 1e-9;  // mm, where the geometry is exact

std::vector<Cutter> all_cutters() {
  return {Cutter::flat(2), Cutter::ball(2),    Cutter::bull(2, 0.5),
          Cutter::flat(6), Cutter::ball(6.35), Cutter::bull(10, 2)};
}

Mesh from_triangles(const std::vector<std::array<Eigen::Vector3d, 3>>& tris) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(3 * tris.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = static_cast<Eigen::Index>(3 * t + k);
      m.V.row(v) = tris[t][k].transpose();
      m.F(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) = static_cast<std::int32_t>(v);
    }
  return m;
}

/// Plane z = p·x + q·y + c as two big triangles over [−L, L]².
Mesh plane(double p, double q, double c, double L = 100) {
  const auto z = [&](double x, double y) { return p * x + q * y + c; };
  const Eigen::Vector3d a(-L, -L, z(-L, -L)), b(L, -L, z(L, -L)), cc(L, L, z(L, L)), d(-L, L, z(-L, L));
  return from_triangles({{a, b, cc}, {a, cc, d}});
}

/// Torus ring radius a = R − r (flat: R, ball: 0) and corner radius r.
double ring(const Cutter& c) { return c.type == CutterType::Ball ? 0.0 : c.radius() - c.corner_radius; }
double corner(const Cutter& c) { return c.type == CutterType::Flat ? 0.0 : c.corner_radius; }

/// Exact CL height against a convex round body of radius rho whose cross-section perpendicular
/// to the cutter's offset is a circle centred at height 0: D = horizontal distance of the axis from
/// the body's axis/centre. Valid for a sphere (D = |c|) and a cylinder along X (D = |y|).
double round_body_cl(const Cutter& c, double rho, double D) {
  const double Dc = std::max(D - ring(c), 0.0);
  const double r = corner(c);
  return std::sqrt((rho + r) * (rho + r) - Dc * Dc) - r;
}

/// f(s) = m·s − h(√(dp² + s²)) maximised over [lo, hi] by ternary search in long double: an
/// oracle independent of the library's Newton iteration.
long double edge_oracle(const Cutter& c, long double m, long double dp, long double lo, long double hi) {
  const long double a = ring(c), r = corner(c);
  const auto h = [&](long double d) -> long double {
    if (d <= a) return 0;
    const long double u = d - a;
    return r - std::sqrt(std::max(0.0L, r * r - u * u));
  };
  const auto f = [&](long double s) {
    return m * s - h(std::min<long double>(c.radius(), std::sqrt(dp * dp + s * s)));
  };
  for (int i = 0; i < 400 && hi - lo > 1e-18L; ++i) {
    const long double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (f(m1) < f(m2))
      lo = m1;
    else
      hi = m2;
  }
  return f(0.5L * (lo + hi));
}

struct Sampler {
  std::mt19937_64 rng;
  explicit Sampler(std::uint64_t seed) : rng(seed) {}
  double u(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
};

/// No point of the mesh (vertices + samples on every triangle) lies above the cutter at p, and the
/// reported contact point touches it.
void expect_touching_not_penetrating(const Mesh& m, const Cutter& c, const CLPoint& p, Sampler& s) {
  ASSERT_NE(p.contact, Contact::None);
  const double R = c.radius();
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d A = m.V.row(m.F(f, 0)), B = m.V.row(m.F(f, 1)), C = m.V.row(m.F(f, 2));
    for (int k = 0; k < 60; ++k) {
      double u = s.u(0, 1), v = s.u(0, 1);
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      const Eigen::Vector3d q = A + u * (B - A) + v * (C - A);
      const double d = std::hypot(q.x() - p.x, q.y() - p.y);
      if (d <= R) {
        EXPECT_LE(q.z() - c.profile_height(d), p.z + 1e-9) << c.describe();
      }
    }
  }
  const double dcc = std::hypot(p.cc.x() - p.x, p.cc.y() - p.y);
  EXPECT_LE(dcc, R + 1e-9);
  EXPECT_NEAR(p.cc.z() - c.profile_height(std::min(dcc, R)), p.z, 1e-9) << c.describe();
}

}  // namespace

TEST(DropCutter, ADrillIsRefusedAndABullWithItsRadiusAsCornerIsTheBall) {
  const Mesh m = plane(0.1, -0.2, 1.5);
  EXPECT_THROW(DropCutter(m, Cutter::drill(5)), millnet::Error);
  const DropCutter bull(m, Cutter::bull(4, 2)), ball(m, Cutter::ball(4));
  for (double x : {-3.0, 0.0, 2.5}) EXPECT_EQ(bull.drop(x, 0.7).z, ball.drop(x, 0.7).z);
}

TEST(DropCutter, HorizontalPlaneIsItsHeight) {
  const Mesh m = plane(0, 0, 3.25);
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.3, -7}, {0, 0}, {12.5, 40}, {-99, 99}}) {
      const CLPoint p = dc.drop(x, y);
      EXPECT_NEAR(p.z, 3.25, kExact) << c.describe();
      EXPECT_NE(p.contact, Contact::None);
    }
  }
}

TEST(DropCutter, TiltedPlaneClosedForm) {
  // tip = plane(axis) + a·tanθ + r/cosθ − r  (flat: R·tanθ, the rim's highest point; ball: R/cosθ − R).
  for (const double deg : {5.0, 20.0, 45.0, 70.0, 85.0})
    for (const double dir : {0.0, 0.7, 2.0, 4.0}) {
      const double t = std::tan(deg * std::numbers::pi / 180);
      const double p = t * std::cos(dir), q = t * std::sin(dir), c0 = 1.5;
      const Mesh m = plane(p, q, c0, 200);
      for (const Cutter& c : all_cutters()) {
        const DropCutter dc(m, c);
        for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.3, -7}, {1, 1}, {-3.7, 2.2}}) {
          const double expect = p * x + q * y + c0 + ring(c) * t + corner(c) / std::cos(std::atan(t)) - corner(c);
          const CLPoint cl = dc.drop(x, y);
          EXPECT_NEAR(cl.z, expect, kExact * std::max(1.0, t)) << c.describe() << " θ=" << deg << " dir=" << dir;
          EXPECT_EQ(cl.contact, Contact::Facet) << c.describe();
        }
      }
    }
}

TEST(DropCutter, SphereCentreDistanceIsRadiusSum) {
  // UV sphere, radius 10: faceted, so the CL is below the exact one by at most the chordal error.
  const double rho = 10;
  const int nu = 360, nv = 180;
  Mesh m;
  m.V.resize((nv + 1) * nu, 3);
  for (int i = 0; i <= nv; ++i)
    for (int j = 0; j < nu; ++j) {
      const double th = std::numbers::pi * i / nv, ph = 2 * std::numbers::pi * j / nu;
      m.V.row(i * nu + j) << rho * std::sin(th) * std::cos(ph), rho * std::sin(th) * std::sin(ph), rho * std::cos(th);
    }
  m.F.resize(2 * nv * nu, 3);
  int t = 0;
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nu; ++j) {
      const int a = i * nu + j, b = i * nu + (j + 1) % nu, c = a + nu, d = b + nu;
      m.F.row(t++) << a, c, d;
      m.F.row(t++) << a, d, b;
    }
  const double sag = rho * (1 - std::cos(std::numbers::pi / nv));  // ≥ chordal error of every facet
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    for (const auto& [x, y] :
         std::vector<std::pair<double, double>>{{0, 0}, {0.4, 0.1}, {3, -2}, {-5, 4.5}, {6.5, 0}}) {
      const double expect = round_body_cl(c, rho, std::hypot(x, y));
      const CLPoint p = dc.drop(x, y);
      EXPECT_LE(p.z, expect + kExact) << c.describe() << " at " << x << "," << y;
      EXPECT_GE(p.z, expect - 2 * sag) << c.describe() << " at " << x << "," << y;
    }
  }
}

TEST(DropCutter, CylinderAlongXMatchesClosedForm) {
  // Half cylinder of radius 5 along X, tessellated in 0.25° strips: chordal error 2.4e-5 mm.
  const double rho = 5;
  const int n = 720;
  const Mesh m = surface([&](double, double) { return 0.0; }, -30, 30, 0, 1, 1, n);
  Mesh cyl = m;
  for (Eigen::Index v = 0; v < cyl.V.rows(); ++v) {
    const double ang = std::numbers::pi * cyl.V(v, 1);  // 0..π
    cyl.V(v, 1) = rho * std::cos(ang);
    cyl.V(v, 2) = rho * std::sin(ang);
  }
  const double sag = rho * (1 - std::cos(std::numbers::pi / n / 2));
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(cyl, c);
    for (const double y : {0.0, 0.3, -1.1, 2.5, -3.9}) {
      const double expect = round_body_cl(c, rho, std::abs(y));
      const CLPoint p = dc.drop(1.234, y);
      EXPECT_LE(p.z, expect + kExact) << c.describe() << " y=" << y;
      EXPECT_GE(p.z, expect - 2 * sag) << c.describe() << " y=" << y;
    }
  }
}

TEST(DropCutter, VerticalStepEdgeContact) {
  // z = 0 for x < 0, z = H for x ≥ 0, a vertical wall at x = 0.
  const double H = 4;
  const Eigen::Vector3d a(-20, -20, 0), b(0, -20, 0), c(0, 20, 0), d(-20, 20, 0);
  const Eigen::Vector3d bt(0, -20, H), ct(0, 20, H), et(20, -20, H), ft(20, 20, H);
  const Mesh m = from_triangles({{a, b, c}, {a, c, d}, {b, bt, ct}, {b, ct, c}, {bt, et, ft}, {bt, ft, ct}});
  for (const Cutter& cut : all_cutters()) {
    const DropCutter dc(m, cut);
    const double R = cut.radius();
    for (const double e : {0.0, 0.1, 0.37, 0.5, 0.8, 0.999, 1.0, 1.5, 2.9, 3.17, 4.9, 6.0}) {
      const double x = -e * R;
      if (x < -15) continue;  // keep the cutter over the modelled ground
      const double expect = std::abs(x) <= R ? H - cut.profile_height(std::abs(x)) : 0.0;
      const CLPoint p = dc.drop(x, 0.3);
      EXPECT_NEAR(p.z, std::max(expect, 0.0), kExact) << cut.describe() << " x=" << x;
      if (x < 0 && -x < R && expect > 0) {
        EXPECT_EQ(p.contact, Contact::Edge) << cut.describe() << " x=" << x;
      }
    }
    EXPECT_NEAR(dc.drop(0.7, 0).z, H, kExact);
  }
}

TEST(DropCutter, SingleTriangleVertexContact) {
  // Apex at the top, the triangle falls steeply away from the axis: only the apex touches.
  const Mesh m = from_triangles({{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(5, -5, -10), Eigen::Vector3d(5, 5, -10)}});
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{-0.3, 0.2}, {-0.6, -0.7}, {-0.05, 0}}) {
      const double d = std::hypot(x, y);
      if (d > c.radius()) continue;
      const CLPoint p = dc.drop(x, y);
      EXPECT_NEAR(p.z, 1 - c.profile_height(d), kExact) << c.describe();
      EXPECT_EQ(p.contact, Contact::Vertex) << c.describe();
      EXPECT_EQ(p.triangle, 0);
      EXPECT_NEAR((p.cc - Eigen::Vector3d(0, 0, 1)).norm(), 0, kExact);
    }
  }
}

TEST(DropCutter, SingleTriangleFacetContact) {
  const double p = 0.3, q = -0.2, c0 = 2;
  const auto z = [&](double x, double y) { return p * x + q * y + c0; };
  const Mesh m = from_triangles({{Eigen::Vector3d(-30, -30, z(-30, -30)), Eigen::Vector3d(30, -30, z(30, -30)),
                                  Eigen::Vector3d(0, 30, z(0, 30))}});
  const double t = std::hypot(p, q);
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    const CLPoint cl = dc.drop(1, -2);
    const double expect = z(1, -2) + ring(c) * t + corner(c) * (std::sqrt(1 + t * t) - 1);
    EXPECT_NEAR(cl.z, expect, kExact) << c.describe();
    EXPECT_EQ(cl.contact, Contact::Facet) << c.describe();
    EXPECT_NEAR(cl.cc.z(), z(cl.cc.x(), cl.cc.y()), kExact);
  }
}

TEST(DropCutter, SingleTriangleHorizontalEdgeContact) {
  // Ridge edge along X at y = 0, z = 2; the triangle falls towards +y; the axis is behind the edge.
  const Mesh m = from_triangles({{Eigen::Vector3d(-10, 0, 2), Eigen::Vector3d(10, 0, 2), Eigen::Vector3d(0, 10, -3)}});
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    for (const double off : {0.05, 0.3, 0.62, 0.75, 0.97}) {
      const double dy = off * c.radius();
      const CLPoint p = dc.drop(0.4, -dy);
      EXPECT_NEAR(p.z, 2 - c.profile_height(dy), kExact) << c.describe() << " dy=" << dy;
      EXPECT_EQ(p.contact, Contact::Edge) << c.describe() << " dy=" << dy;
      EXPECT_NEAR(p.cc.y(), 0, kExact);
      EXPECT_NEAR(p.cc.z(), 2, kExact);
    }
  }
}

TEST(DropCutter, SingleTriangleSlopedEdgeAgainstOneDimensionalOracle) {
  // Sloped ridge from (−10, 0, −3) to (10, 0, 5), falling steeply towards +y: the edge decides.
  const Eigen::Vector3d P(-10, 0, -3), Q(10, 0, 5);
  const Mesh m = from_triangles({{P, Q, Eigen::Vector3d(0, 10, -40)}});
  const double slope = 8.0 / 20.0;
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(m, c);
    for (const double off : {0.01, 0.2, 0.45, 0.55, 0.8, 0.95, 0.999}) {
      const double dp = off * c.radius(), x = 1.3;
      const CLPoint p = dc.drop(x, -dp);
      const double S = std::sqrt(c.radius() * c.radius() - dp * dp);
      const long double best = edge_oracle(c, slope, dp, -S, S);
      const double expect = (P.z() + slope * (x - P.x())) + static_cast<double>(best);
      EXPECT_NEAR(p.z, expect, kExact) << c.describe() << " dp=" << dp;
      EXPECT_EQ(p.contact, Contact::Edge) << c.describe() << " dp=" << dp;
    }
  }
}

TEST(DropCutter, BullEdgeRandomAgainstOneDimensionalOracle) {
  // 20,000 random edges (slope up to ±80°, any distance, any clipping by the edge's ends) for
  // bull noses of several proportions; ball and flat as the limits.
  Sampler s(20261123);
  const std::vector<Cutter> cutters{Cutter::bull(2, 0.5), Cutter::bull(2, 0.05), Cutter::bull(2, 0.95),
                                    Cutter::bull(10, 2),  Cutter::bull(2, 1),    Cutter::ball(2),
                                    Cutter::flat(2)};
  int n = 0;
  for (const Cutter& c : cutters) {
    const double R = c.radius();
    for (int k = 0; k < 3000; ++k) {
      const double ang = s.u(0, 2 * std::numbers::pi);
      const double slope = std::tan(s.u(-1.4, 1.4));
      const double dp = s.u(0, R) * (k % 10 == 0 ? 1e-3 : 1.0);
      const double t0 = s.u(-2 * R, 2 * R), len = s.u(0.01, 3 * R);
      // Edge through the foot (dp to the left of the direction), parameter from t0 to t0 + len.
      const Eigen::Vector2d u(std::cos(ang), std::sin(ang)), nrm(-u.y(), u.x());
      const Eigen::Vector2d foot = dp * nrm;
      const Eigen::Vector2d a = foot + t0 * u, b = foot + (t0 + len) * u;
      const double za = 1 + slope * t0, zb = 1 + slope * (t0 + len);
      // Third vertex far below, behind the edge: it can never be the contact.
      const Eigen::Vector2d w = foot + (t0 + 0.5 * len) * u + 50 * nrm;
      const Mesh m = from_triangles({{Eigen::Vector3d(a.x(), a.y(), za), Eigen::Vector3d(b.x(), b.y(), zb),
                                      Eigen::Vector3d(w.x(), w.y(), -1000)}});
      const double S = std::sqrt(std::max(0.0, R * R - dp * dp));
      const double lo = std::max(t0, -S), hi = std::min(t0 + len, S);
      if (lo > hi) continue;
      const double expect = 1 + static_cast<double>(edge_oracle(c, slope, dp, lo, hi));
      const CLPoint p = drop_brute_force(m, c, 0, 0);
      EXPECT_NEAR(p.z, expect, kExact * std::max(1.0, std::abs(slope))) << c.describe() << " k=" << k;
      ++n;
    }
  }
  EXPECT_GT(n, 5000);
}

TEST(DropCutter, RandomTrianglesTouchWithoutPenetrating) {
  Sampler s(42);
  for (const Cutter& c : all_cutters()) {
    for (int k = 0; k < 60; ++k) {
      const double R = c.radius();
      std::array<Eigen::Vector3d, 3> t;
      for (auto& v : t) v = Eigen::Vector3d(s.u(-1.5 * R, 1.5 * R), s.u(-1.5 * R, 1.5 * R), s.u(-2, 2));
      const Mesh m = from_triangles({t});
      const CLPoint p = drop_brute_force(m, c, s.u(-0.5 * R, 0.5 * R), s.u(-0.5 * R, 0.5 * R));
      if (p.contact == Contact::None) continue;
      expect_touching_not_penetrating(m, c, p, s);
    }
  }
}

TEST(DropCutter, RandomMeshesMatchBruteForce) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    Sampler s(seed);
    // A triangle soup: small and large, flat, steep and vertical triangles, some far off.
    std::vector<std::array<Eigen::Vector3d, 3>> tris;
    for (int k = 0; k < 400; ++k) {
      const double cx = s.u(0, 30), cy = s.u(0, 30), sz = k % 40 == 0 ? 15 : s.u(0.05, 3);
      std::array<Eigen::Vector3d, 3> t;
      for (auto& v : t) v = Eigen::Vector3d(cx + s.u(-sz, sz), cy + s.u(-sz, sz), s.u(0, 5));
      if (k % 17 == 0) t[1].head<2>() = t[0].head<2>();                                            // vertical edge
      if (k % 23 == 0) t[2].head<2>() = t[0].head<2>() + 0.5 * (t[1].head<2>() - t[0].head<2>());  // vertical facet
      tris.push_back(t);
    }
    const Mesh soup = from_triangles(tris);
    // A noisy terrain.
    const Mesh terrain = surface(
        [&](double x, double y) { return 2 * std::sin(0.7 * x) * std::cos(0.4 * y) + 0.3 * std::sin(5 * x + 3 * y); },
        0, 25, 0, 20, 40, 31);
    // A closed part with vertical walls and a base below the top.
    const Mesh part =
        solid([&](double x, double y) { return 6 + 2 * std::cos(0.5 * x) * std::sin(0.3 * y); }, 2, 28, 3, 27, 26, 24);
    for (const Mesh* m : {&soup, &terrain, &part})
      for (const Cutter& c : all_cutters()) {
        const DropCutter dc(*m, c);
        std::vector<Eigen::Vector2d> pts;
        for (int k = 0; k < 300; ++k) pts.emplace_back(s.u(-5, 35), s.u(-5, 35));
        const std::vector<CLPoint> got = dc.drop(pts);
        for (std::size_t k = 0; k < pts.size(); ++k) {
          const CLPoint ref = drop_brute_force(*m, c, pts[k].x(), pts[k].y());
          ASSERT_EQ(got[k].z, ref.z) << c.describe() << " seed " << seed << " at " << pts[k].transpose();
          // The whole contact, ties included (the lowest triangle wins), whatever the hint.
          const auto nf = static_cast<std::int32_t>(m->F.rows());
          const auto hint = static_cast<std::int32_t>(k * 7919 % static_cast<std::size_t>(nf));
          for (const CLPoint& p : {got[k], dc.drop(pts[k].x(), pts[k].y(), hint), dc.drop(pts[k].x(), pts[k].y())}) {
            ASSERT_EQ(p.z, ref.z);
            ASSERT_EQ(p.contact, ref.contact) << c.describe() << " seed " << seed << " at " << pts[k].transpose();
            ASSERT_EQ(p.triangle, ref.triangle) << c.describe() << " seed " << seed << " at " << pts[k].transpose();
            ASSERT_EQ(p.cc, ref.cc);
          }
          if (k % 50 == 0 && ref.contact != Contact::None) expect_touching_not_penetrating(*m, c, got[k], s);
        }
      }
  }
}

TEST(DropCutter, NoTriangleUnderTheCutterIsNoContact) {
  const Mesh m = plane(0, 0, 1, 5);
  const DropCutter dc(m, Cutter::ball(2));
  const CLPoint p = dc.drop(50, 50);
  EXPECT_EQ(p.contact, Contact::None);
  EXPECT_TRUE(std::isinf(p.z) && p.z < 0);
  EXPECT_EQ(p.triangle, -1);
  EXPECT_NEAR(dc.drop(5.9, 0).z, 1 - Cutter::ball(2).profile_height(0.9), kExact);  // overhang still touches
  const std::vector<double> g = dc.drop_grid(-10, 0, 1, 21, 1);
  EXPECT_TRUE(std::isinf(g[0]) && g[0] < 0);
  EXPECT_EQ(g[10], 1);
}

TEST(DropCutter, InvalidInputThrows) {
  Mesh empty;
  EXPECT_THROW(DropCutter(empty, Cutter::ball(2)), millnet::Error);
  EXPECT_THROW(DropCutter(plane(0, 0, 0), Cutter::flat(-2)), millnet::Error);
}

TEST(DropCutter, GridMatchesSingleDrops) {
  const Mesh terrain = surface([](double x, double y) { return std::sin(x) * std::cos(1.3 * y); }, 0, 10, 0, 8, 50, 40);
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(terrain, c);
    const std::vector<double> g = dc.drop_grid(-1, -0.5, 0.37, 33, 27);
    for (int i = 0; i < 27; ++i)
      for (int j = 0; j < 33; ++j)
        ASSERT_EQ(g[static_cast<std::size_t>(i * 33 + j)], dc.drop(-1 + j * 0.37, -0.5 + i * 0.37).z);
  }
}

TEST(DropCutter, ThreadCountInvariant) {
  const Mesh terrain =
      surface([](double x, double y) { return std::sin(x) * std::cos(1.3 * y) + 0.01 * x * y; }, 0, 20, 0, 15, 120, 90);
  const int saved = omp_get_max_threads();
  for (const Cutter& c : all_cutters()) {
    const DropCutter dc(terrain, c);
    std::vector<Eigen::Vector2d> pts;
    Sampler s(9);
    for (int k = 0; k < 3000; ++k) pts.emplace_back(s.u(-2, 22), s.u(-2, 17));
    omp_set_num_threads(1);
    const auto g1 = dc.drop_grid(-1, -1, 0.13, 170, 131);
    const auto p1 = dc.drop(pts);
    omp_set_num_threads(2);
    const auto g2 = dc.drop_grid(-1, -1, 0.13, 170, 131);
    const auto p2 = dc.drop(pts);
    ASSERT_EQ(g1, g2) << c.describe();
    for (std::size_t k = 0; k < pts.size(); ++k) {
      ASSERT_EQ(p1[k].z, p2[k].z);
      ASSERT_EQ(p1[k].contact, p2[k].contact);
      ASSERT_EQ(p1[k].triangle, p2[k].triangle);
      ASSERT_EQ(p1[k].cc, p2[k].cc);
    }
  }
  omp_set_num_threads(saved);
}

TEST(DropCutter, FarFromTheOriginKeepsPrecision) {
  // The tilted-plane closed form, with the part 5 m away from the origin.
  const double ox = 5000, oy = -3000, oz = 200, p = 0.4, q = -0.25;
  const double L = 50;
  const auto z = [&](double x, double y) { return p * (x - ox) + q * (y - oy) + oz; };
  const Eigen::Vector3d a(ox - L, oy - L, z(ox - L, oy - L)), b(ox + L, oy - L, z(ox + L, oy - L)),
      c(ox + L, oy + L, z(ox + L, oy + L)), d(ox - L, oy + L, z(ox - L, oy + L));
  const Mesh m = from_triangles({{a, b, c}, {a, c, d}});
  const double t = std::hypot(p, q);
  for (const Cutter& cut : all_cutters()) {
    const DropCutter dc(m, cut);
    const double x = ox + 1.234567, y = oy - 7.654321;
    const double expect = z(x, y) + ring(cut) * t + corner(cut) * (std::sqrt(1 + t * t) - 1);
    EXPECT_NEAR(dc.drop(x, y).z, expect, kExact) << cut.describe();
  }
}

TEST(DropCutter, BullEdgeDegenerateCases) {
  // Edges at exactly the ring radius a, grazing the rim, nearly vertical, very short, horizontal.
  const Cutter c = Cutter::bull(4, 0.7);  // a = 1.3
  const double R = c.radius(), a = ring(c);
  int n = 0;
  for (const double dp : {0.0, 1e-12, a - 1e-12, a, a + 1e-12, 0.5 * (a + R), R - 1e-9, R - 1e-12})
    for (const double slope : {0.0, 1e-9, 0.3, -2.0, 40.0, -1e3, 1e4})
      for (const double t0 : {-3.0, -0.5, 0.0, 1e-9, 0.8})
        for (const double len : {1e-6, 0.01, 0.7, 6.0}) {
          const Eigen::Vector2d u(0.6, 0.8), nrm(-0.8, 0.6);
          const Eigen::Vector2d a2 = dp * nrm + t0 * u, b2 = dp * nrm + (t0 + len) * u;
          const Eigen::Vector2d w = dp * nrm + (t0 + 0.5 * len) * u + 50 * nrm;
          const Mesh m = from_triangles(
              {{Eigen::Vector3d(a2.x(), a2.y(), 1 + slope * t0),
                Eigen::Vector3d(b2.x(), b2.y(), 1 + slope * (t0 + len)), Eigen::Vector3d(w.x(), w.y(), -1e5)}});
          const double S = std::sqrt(std::max(0.0, R * R - dp * dp));
          const double lo = std::max(t0, -S), hi = std::min(t0 + len, S);
          const CLPoint p = drop_brute_force(m, c, 0, 0);
          if (lo > hi) continue;
          const double expect = 1 + static_cast<double>(edge_oracle(c, slope, dp, lo, hi));
          EXPECT_NEAR(p.z, expect, kExact * std::max(1.0, std::abs(slope)))
              << "dp=" << dp << " slope=" << slope << " t0=" << t0 << " len=" << len;
          ++n;
        }
  EXPECT_GT(n, 500);
}

TEST(DropCutter, TheSamplersMemoAnswersEachSamplerWithItsOwnDrops) {
  // The strategies' sampler keeps its thread's last answers by the point's bits. Two samplers over
  // different surfaces, asked for the same points in turn, and a third made where the first was,
  // must each answer with their own drop-cutter's drops, asked again or not; every ask counts.
  const Mesh low = plane(0.1, -0.05, 0.0), high = plane(-0.2, 0.1, 3.0);
  const DropCutter dl(low, Cutter::ball(2)), dh(high, Cutter::ball(2));
  auto expect_own = [](const detail::Sampler& s, const DropCutter& d, double x, double y) {
    const CLPoint c = d.drop(x, y);
    EXPECT_EQ(s.z(x, y), c.z) << x << " " << y;
    EXPECT_EQ(s.sample(x, y).p.z(), c.z) << x << " " << y;
  };
  for (int round = 0; round < 2; ++round) {
    const detail::Sampler sl(low, dl), sh(high, dh);
    for (int k = 0; k < 50; ++k) {
      const double x = -20 + 0.7 * k, y = 5 - 0.3 * k;
      expect_own(round == 0 ? sl : sh, round == 0 ? dl : dh, x, y);
      expect_own(round == 0 ? sh : sl, round == 0 ? dh : dl, x, y);
    }
    EXPECT_EQ(sl.drops(), 100U);
    EXPECT_EQ(sh.drops(), 100U);
  }
}
