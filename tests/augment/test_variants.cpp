// Variants: the default list, identity at 0°, 90° and 180° turns of an asymmetric surface's grid.
#include "ingest/builders.hpp"
#include "millnet/augment/variants.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace millnet;
using namespace millnet::augment;
using millnet::testing_ingest::solid;

namespace {
// A square part whose grid has no symmetry: ramp along x plus an off-centre bump.
ingest::Mesh asymmetric_part() {
  return solid(
      [](double x, double y) { return 10 + 0.2 * x + 6 * std::exp(-((x - 12) * (x - 12) + (y - 30) * (y - 30)) / 40); },
      0, 42, 0, 42, 84, 84);
}
}  // namespace

TEST(Augment, DefaultsGive22VariantsInDocumentedOrder) {
  const AugmentParams p = AugmentParams::defaults();
  ASSERT_EQ(p.angles_deg.size(), 11u);
  EXPECT_EQ(p.angles_deg.front(), -50.0);
  EXPECT_EQ(p.angles_deg[5], 0.0);
  EXPECT_EQ(p.angles_deg.back(), 50.0);
  const auto v = make_variants("part_a", p);
  ASSERT_EQ(v.size(), 22u);
  for (std::size_t k = 0; k < v.size(); ++k) {
    EXPECT_EQ(v[k].source, "part_a");
    EXPECT_EQ(v[k].axis, Axis::X);
    EXPECT_EQ(v[k].flip, k >= 11);
    EXPECT_EQ(v[k].angle_deg, -50.0 + 10.0 * static_cast<double>(k % 11));
  }
  AugmentParams q;
  q.angles_deg = {0, 30};
  q.axes = {Axis::X, Axis::Y, Axis::Z};
  q.flip = false;
  const auto w = make_variants("p", q);
  ASSERT_EQ(w.size(), 6u);
  EXPECT_EQ(w[2].axis, Axis::Y);
  EXPECT_EQ(w[3].angle_deg, 30.0);
  q.angles_deg.clear();
  EXPECT_THROW((void)make_variants("p", q), millnet::Error);
  EXPECT_EQ(parse_axis("Y"), Axis::Y);
  EXPECT_EQ(to_char(Axis::Z), 'z');
  EXPECT_THROW((void)parse_axis("w"), millnet::Error);
}

TEST(Augment, ZeroRotationChangesNothing) {
  const ingest::Mesh m = asymmetric_part();
  for (Axis a : {Axis::X, Axis::Y, Axis::Z}) {
    const ingest::Mesh r = apply(m, Variant{"p", a, 0.0, false});
    EXPECT_EQ(r.V, m.V);
    EXPECT_EQ(r.F, m.F);
  }
}

TEST(Augment, QuarterAndHalfTurnsAboutUpPermuteTheGrid) {
  const ingest::Mesh m = asymmetric_part();
  const int n = 15;
  const Eigen::MatrixXd g = ingest::sample_grid(m, 0.5, n).h;
  // 90° CCW about Z through the centre: (x, y) → (c − (y − c), x), so G'(r, c) = G(n−1−c, r).
  const Eigen::MatrixXd q = ingest::sample_grid(apply(m, Variant{"p", Axis::Z, 90.0, false}), 0.5, n).h;
  // 180° flip: G'(r, c) = G(n−1−r, n−1−c).
  const Eigen::MatrixXd h = ingest::sample_grid(apply(m, Variant{"p", Axis::X, 0.0, true}), 0.5, n).h;
  double qmax = 0, hmax = 0;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      qmax = std::max(qmax, std::abs(q(r, c) - g(n - 1 - c, r)));
      hmax = std::max(hmax, std::abs(h(r, c) - g(n - 1 - r, n - 1 - c)));
    }
  EXPECT_LT(qmax, 1e-9);
  EXPECT_LT(hmax, 1e-9);
  // And the grid is not symmetric, so the permutation is really tested.
  EXPECT_GT((g - g.transpose()).cwiseAbs().maxCoeff(), 1.0);
  EXPECT_GT((g - g.colwise().reverse()).cwiseAbs().maxCoeff(), 1.0);
}

TEST(Augment, RotationsAreRigidAboutTheBoxCentre) {
  const ingest::Mesh m = asymmetric_part();
  for (const Variant& v : make_variants("p", AugmentParams::defaults())) {
    const ingest::Mesh r = apply(m, v);
    // Edge lengths preserved (rigid), winding kept (proper rotation: signed volume unchanged).
    double vol_m = 0, vol_r = 0;
    for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
      const Eigen::Vector3d a = m.V.row(m.F(t, 0)), b = m.V.row(m.F(t, 1)), c = m.V.row(m.F(t, 2));
      const Eigen::Vector3d ra = r.V.row(m.F(t, 0)), rb = r.V.row(m.F(t, 1)), rc = r.V.row(m.F(t, 2));
      ASSERT_NEAR((b - a).norm(), (rb - ra).norm(), 1e-9);
      vol_m += a.dot(b.cross(c)) / 6;
      vol_r += ra.dot(rb.cross(rc)) / 6;
    }
    EXPECT_NEAR(vol_m, vol_r, 1e-6 * std::abs(vol_m));
    EXPECT_GT(vol_m, 0);
  }
  // A tilt of 30° about X: a point at the centre + (0, 10, 0) goes to centre + (0, 10cos30, 10sin30).
  ingest::Mesh probe = m;
  const ingest::Box3 b = ingest::bounds(m);
  const Eigen::Vector3d c = 0.5 * (b.min + b.max);
  probe.V.row(0) = (c + Eigen::Vector3d(0, 10, 0)).transpose();
  probe.V.row(1) = (c + Eigen::Vector3d(0, -30, -30)).transpose();  // keep the box the same size or larger
  const ingest::Mesh turned = apply(probe, Variant{"p", Axis::X, 30.0, false});
  const ingest::Box3 pb = ingest::bounds(probe);
  const Eigen::Vector3d pc = 0.5 * (pb.min + pb.max);
  const Eigen::Vector3d expect =
      pc + Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitX()) * (c + Eigen::Vector3d(0, 10, 0) - pc);
  EXPECT_LT((turned.V.row(0).transpose() - expect).norm(), 1e-12);
  EXPECT_NEAR((turned.V.row(0).transpose() - pc).norm(), (c + Eigen::Vector3d(0, 10, 0) - pc).norm(), 1e-12);
}
