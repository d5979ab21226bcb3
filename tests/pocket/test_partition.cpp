// SRPs, T-partition and I-partition on hand-made pockets (scan lines horizontal, tool R = 5 mm).
#include "millnet/pocket/partition.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace millnet::pocket;

namespace {

constexpr double kR = 5.0;

Loop rect(double x0, double y0, double x1, double y1, bool ccw) {
  Loop l{{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  if (!ccw) std::reverse(l.begin(), l.end());
  return l;
}

/// Circle as two half arcs, clockwise (an island).
Loop circle_cw(double cx, double cy, double r) { return {{cx - r, cy, -1}, {cx + r, cy, -1}}; }

std::vector<PolyArea> reach(const Region& r, double angle_deg = 0) {
  return to_scan_frame(offset_inward(r, kR), angle_deg);
}

int count_kind(const std::vector<Srp>& s, SrpKind k) {
  return static_cast<int>(std::count_if(s.begin(), s.end(), [&](const Srp& x) { return x.kind == k; }));
}

double ring_area(const std::vector<Vec2>& pts) {
  double s = 0;
  for (std::size_t k = 0; k < pts.size(); ++k)
    s += pts[k].x() * pts[(k + 1) % pts.size()].y() - pts[k].y() * pts[(k + 1) % pts.size()].x();
  return 0.5 * s;
}

double areas_area(const std::vector<PolyArea>& as) {
  double s = 0;
  for (const auto& a : as) {
    s += std::abs(ring_area(a.outer));
    for (const auto& h : a.holes) s -= std::abs(ring_area(h));
  }
  return s;
}

/// The checks every partition must pass: the built faces match the seeds' count, every face is
/// y-monotone by an independent scan at random heights (fixed seed), no area is lost but the slits.
void check_partition(const std::vector<PolyArea>& areas, const Partition& p) {
  EXPECT_EQ(static_cast<int>(p.faces.size()), p.formula_regions());
  std::mt19937 rng(12345);
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    const auto& face = p.faces[f];
    EXPECT_TRUE(face.holes.empty()) << "face " << f;
    double lo = 1e18, hi = -1e18;
    for (const Vec2& v : face.outer) {
      lo = std::min(lo, v.y());
      hi = std::max(hi, v.y());
    }
    std::uniform_real_distribution<double> U(lo, hi);
    for (int k = 0; k < 400; ++k) {
      const double y = U(rng);
      EXPECT_LE(scan_intervals(face, y).size(), 1u) << "face " << f << " y " << y;
    }
  }
  double cut_len = 0;
  for (const Cut& c : p.cuts)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) cut_len += (c.pts[k + 1] - c.pts[k]).norm();
  const double lost = areas_area(areas) - areas_area(p.faces);
  EXPECT_GE(lost, -1e-6);
  EXPECT_LE(lost, (cut_len + 1.0) * 2 * tol::slit_half_mm * 1.5 + 1e-6);
}

}  // namespace

TEST(Partition, RectangleHasNoSrpAndOneRegion) {
  Region r{rect(0, 0, 100, 60, true), {}};
  const auto a = reach(r);
  EXPECT_TRUE(find_srps(a).empty());
  const Partition p = partition(a, PartitionKind::T);
  EXPECT_EQ(p.faces.size(), 1u);
  check_partition(a, p);
}

TEST(Partition, DiamondIslandTwoSrpsTwoRegions) {
  // Rotated square island (half-diagonal 10) at (50, 30); grown by R its top and bottom are arcs.
  Region r{rect(0, 0, 100, 60, true), {{{50, 20, 0}, {40, 30, 0}, {50, 40, 0}, {60, 30, 0}}}};
  const auto a = reach(r);
  const auto s = find_srps(a);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(count_kind(s, SrpKind::R), 1);
  EXPECT_EQ(count_kind(s, SrpKind::L), 1);
  for (const Srp& x : s) {
    EXPECT_NEAR(x.p.x(), 50.0, 0.2);
    EXPECT_NEAR(x.p.y(), x.kind == SrpKind::R ? 45.0 : 15.0, 2e-3);
    EXPECT_EQ(x.loop, 1);
  }
  const Partition p = partition(a, PartitionKind::T);
  EXPECT_EQ(p.faces.size(), 2u);  // n_s − n_i + 1 = 2 − 1 + 1
  check_partition(a, p);
}

TEST(Partition, CombWithThreeProngs) {
  // The bench comb: two notches between three upward prongs ⇒ 2 L-SRPs (notch floors) ⇒ 3 regions.
  Region r{{{0, 0, 0},
            {140, 0, 0},
            {140, 90, 0},
            {110, 90, 0},
            {110, 30, 0},
            {85, 30, 0},
            {85, 90, 0},
            {55, 90, 0},
            {55, 30, 0},
            {30, 30, 0},
            {30, 90, 0},
            {0, 90, 0}},
           {}};
  const auto a = reach(r);
  const auto s = find_srps(a);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(count_kind(s, SrpKind::L), 2);
  for (const Srp& x : s) {
    EXPECT_NEAR(x.p.y(), 25.0, 1e-3);  // notch floor at 30 grown by R
    EXPECT_EQ(x.loop, 0);
  }
  const Partition p = partition(a, PartitionKind::T);
  EXPECT_EQ(p.faces.size(), 3u);
  check_partition(a, p);
  // Upside down (passes reversed) the floors become maxima: 2 R-SRPs, still 3 regions.
  const auto b = reach(r, 180);
  const auto s2 = find_srps(b);
  EXPECT_EQ(count_kind(s2, SrpKind::R), 2);
  EXPECT_EQ(s2.size(), 2u);
  // Scan lines along the prongs (90°): the comb is monotone across them ⇒ 0 SRPs, 1 region.
  const auto c = reach(r, 90);
  EXPECT_TRUE(find_srps(c).empty());
  EXPECT_EQ(partition(c, PartitionKind::T).faces.size(), 1u);
}

TEST(Partition, ArcIslandAtEveryAngle) {
  // Circle island (two bulge −1 arcs): flattened by Clipper, it must still give exactly one top and
  // one bottom SRP at every direction (flat-top merging and noise rejection).
  Region r{rect(0, 0, 100, 80, true), {circle_cw(50, 40, 10)}};
  for (double ang = 0; ang < 180; ang += 7) {
    const auto a = reach(r, ang);
    const auto s = find_srps(a);
    ASSERT_EQ(s.size(), 2u) << "angle " << ang;
    EXPECT_EQ(count_kind(s, SrpKind::R), 1);
    const Vec2 c = to_scan_frame(Vec2(50, 40), ang);
    for (const Srp& x : s) EXPECT_NEAR(std::abs(x.p.y() - c.y()), 15.0, 2e-3) << "angle " << ang;
    const Partition p = partition(a, PartitionKind::T);
    EXPECT_EQ(p.faces.size(), 2u) << "angle " << ang;
    check_partition(a, p);
  }
}

TEST(Partition, FourRoundIslandsFormulaAndFaces) {
  Region r{rect(0, 0, 120, 100, true),
           {circle_cw(35, 30, 15), circle_cw(85, 30, 15), circle_cw(35, 70, 15), circle_cw(85, 70, 15)}};
  for (double ang : {0.0, 10.0, 45.0, 90.0, 133.0}) {
    const auto a = reach(r, ang);
    const Partition t = partition(a, PartitionKind::T);
    EXPECT_EQ(t.srps.size(), 8u) << ang;
    EXPECT_EQ(t.faces.size(), 8u - 4u + 1u) << ang;
    check_partition(a, t);
    const Partition i = partition(a, PartitionKind::I);
    EXPECT_LE(i.faces.size(), t.faces.size());
    EXPECT_EQ(static_cast<int>(i.faces.size()), static_cast<int>(t.faces.size()) - i.nls);
    check_partition(a, i);
  }
}

TEST(Partition, OneNlsRemovesExactlyOneRegion) {
  // Seed Fig. 5(b): island B lies entirely above island A and to its right (disjoint projections on
  // the normal axis). T: 4 SRPs, 2 islands ⇒ 3 regions; I: A's top joined to B's bottom by one
  // NLS + scan-line cut ⇒ 2 regions.
  Region r{rect(0, 0, 120, 100, true), {rect(20, 15, 40, 35, false), rect(70, 60, 90, 80, false)}};
  const auto a = reach(r);
  const Partition t = partition(a, PartitionKind::T);
  EXPECT_EQ(t.srps.size(), 4u);
  EXPECT_EQ(t.faces.size(), 3u);
  check_partition(a, t);
  const Partition i = partition(a, PartitionKind::I);
  EXPECT_EQ(i.nls, 1);
  EXPECT_EQ(i.faces.size(), 2u);
  check_partition(a, i);
  // The NLS cut starts at A's top (y = 40) and ends at B's bottom (y = 55).
  int n_nls = 0;
  for (const Cut& c : i.cuts)
    if (c.nls) {
      ++n_nls;
      ASSERT_EQ(c.pts.size(), 3u);
      EXPECT_NEAR(c.pts.front().y(), 40.0, 1e-6);
      EXPECT_NEAR(c.pts.back().y(), 55.0, 1e-6);
      EXPECT_NEAR(c.pts[0].x(), c.pts[1].x(), 1e-9);  // the NLS part is normal to the scan lines
    }
  EXPECT_EQ(n_nls, 1);
}

TEST(Partition, NoNlsWhenIslandsShareScanLines) {
  // Two islands side by side (overlapping y-projections: one group): no L-SRP lies above an
  // R-SRP of another group, so the I-partition equals the T-partition.
  Region r{rect(0, 0, 120, 60, true), {rect(20, 20, 40, 40, false), rect(70, 15, 90, 45, false)}};
  const auto a = reach(r);
  const Partition t = partition(a, PartitionKind::T);
  const Partition i = partition(a, PartitionKind::I);
  EXPECT_EQ(t.faces.size(), 3u);
  EXPECT_EQ(i.nls, 0);
  EXPECT_EQ(i.faces.size(), 3u);
  check_partition(a, i);
}

TEST(Partition, BlockedPairKeepsTCuts) {
  // A's top (y = 35 after growing) lies below B's bottom (y = 60), islands in different groups, but a
  // slot cut from the left wall (y ∈ [45, 50], to x = 100; grown: y ∈ [40, 55], x ≤ 105) lies
  // between them: every NLS + scan-line path from A to B is blocked, so no pair is made. The slot's
  // walls are y-monotone (no SRP), so T has 4 SRPs, 2 islands ⇒ 3 regions.
  Region r{{{0, 0, 0}, {120, 0, 0}, {120, 100, 0}, {0, 100, 0}, {0, 50, 0}, {100, 50, 0}, {100, 45, 0}, {0, 45, 0}},
           {rect(20, 15, 40, 30, false), rect(70, 65, 90, 80, false)}};
  const auto a = reach(r);
  ASSERT_EQ(a.size(), 1u);
  const Partition t = partition(a, PartitionKind::T);
  EXPECT_EQ(t.srps.size(), 4u);
  EXPECT_EQ(t.faces.size(), 3u);
  const Partition i = partition(a, PartitionKind::I);
  EXPECT_EQ(i.nls, 0);
  EXPECT_EQ(i.faces.size(), t.faces.size());
  check_partition(a, t);
  check_partition(a, i);
}
