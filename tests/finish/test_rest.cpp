// Rest finishing (issue 41): an L-shaped concave corner (a wall at x = 0 rising to z = 10, a 1 mm
// fillet, a floor at z = 0) finished by a Ø6 ball leaves, behind it, material a Ø2 ball can take.
// By hand (the Ø6 ball in the corner: centre (3, 3)): a floor point (x, 0) is at
// √((3 − x)² + 9) − 3 from it, so with the threshold t the Ø2 axis positions that cut rest are
// 1 < x < 3 − √(6t + t²) (2.6530 for t = 0.02; left of 1 the Ø2 sits on the wall's top edge); the
// wall's rest reaches up to where the Ø6 touches it, z = 3 − √(6t + t²). Oracles: those formulas,
// and the ball's centre distance to every triangle (brute force) for gouge and for coverage.
#include "rest_internal.hpp"
#include "sampling.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/finish/tolerances.hpp"
#include "millnet/gcode/stats.hpp"

#include <gtest/gtest.h>

#include <random>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <variant>
#include <vector>

namespace millnet::finish {
namespace {

using tooling::Cutter;

constexpr double kT = 0.02;                                         // threshold, mm
const double kBandEnd = 3 - std::sqrt(6 * kT + kT * kT);            // 2.65302
double floor_rest(double x) { return std::hypot(3 - x, 3.0) - 3; }  // x in [1, 3]
const double kTouched = 3 - std::sqrt(6 * kT / 2 + kT * kT / 4);    // 2.7548: rest over kT / 2 ends

/// An XZ profile extruded along Y over [0, length]: two triangles per profile segment.
ingest::Mesh extruded(const std::vector<Eigen::Vector2d>& prof, double length) {
  ingest::Mesh m;
  const auto n = static_cast<Eigen::Index>(prof.size());
  m.V.resize(2 * n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    m.V.row(k) << prof[static_cast<std::size_t>(k)].x(), 0, prof[static_cast<std::size_t>(k)].y();
    m.V.row(n + k) << prof[static_cast<std::size_t>(k)].x(), length, prof[static_cast<std::size_t>(k)].y();
  }
  m.F.resize(2 * (n - 1), 3);
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    m.F.row(2 * k) << static_cast<int>(k), static_cast<int>(k + 1), static_cast<int>(n + k + 1);
    m.F.row(2 * k + 1) << static_cast<int>(k), static_cast<int>(n + k + 1), static_cast<int>(n + k);
  }
  return m;
}

/// The corner's profile in XZ extruded along Y over [0, 30]: top z = 10 for x in [−10, 0], the wall
/// x = 0 down to z = 1, the fillet (centre (1, 1), radius 1, 64 chords), the floor to x = 20.
ingest::Mesh l_corner() {
  std::vector<Eigen::Vector2d> prof{{-10, 10}, {0, 10}};
  for (int k = 0; k <= 64; ++k) {
    const double t = 0.5 * std::numbers::pi * k / 64;
    prof.emplace_back(1 - std::cos(t), 1 - std::sin(t));
  }
  prof.emplace_back(20, 0);
  return extruded(prof, 30);
}

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5).
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double distance_to_mesh(const ingest::Mesh& m, const Eigen::Vector3d& p) {
  double best = HUGE_VAL;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {  // O(#F)
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    best = std::min(best, (closest_on_triangle(p, a, b, c) - p).norm());
  }
  return best;
}

FinishParams rest_params() {
  FinishParams p;
  p.tool = Cutter::ball(2);
  p.stepover_mm = 0.2;
  p.step_down_mm = 0.04;
  p.chord_tolerance_mm = 0.005;
  p.safe_z_mm = 20;
  return p;
}

/// The corner's rest for the Ø2 behind a Ø6 ball at the threshold kT, over the part's box.
RestRegions behind_six(const ingest::Mesh& part, const DropCutter& two) {
  RestParams rp;
  rp.reference = Cutter::ball(6);
  rp.threshold_mm = kT;
  return rest_regions(part, two, rp, -10, 0, 20, 30);
}

TEST(RestRegions, TheCornerBandBehindASixMillimetreBallIsTheHandComputedOne) {
  const ingest::Mesh part = l_corner();
  const DropCutter two(part, Cutter::ball(2));
  const RestRegions r = behind_six(part, two);
  EXPECT_NEAR(r.cell, rest_cell_mm(Cutter::ball(6), kT), 1e-12);
  EXPECT_NEAR(r.cell, std::sqrt(2 * 3 * kT / 4 - kT * kT / 16) * std::numbers::sqrt2, 1e-12);  // 0.2449
  std::size_t checked = 0;
  for (int i = 0; i < r.ny; ++i) {
    const double y = r.y0 + r.cell * i;
    if (y < 8 || y > 22) continue;  // the open ends let the Ø6 in from the side
    for (int j = 0; j < r.nx; ++j) {
      const double x = r.x0 + r.cell * j;
      const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(r.nx) + static_cast<std::size_t>(j);
      if (std::abs(x - 1) < r.cell || std::abs(x - kBandEnd) < r.cell) continue;
      const bool in_band = x > 1 && x < kBandEnd;
      EXPECT_EQ(r.mask[k] == 1 || (r.mask[k] == 2 && r.thickness[k] > kT), in_band) << x << " " << y;
      if (in_band) {  // the Ø2 stands on the floor at (x, 0): the material there, by hand
        EXPECT_NEAR(r.thickness[k], floor_rest(x), 0.004) << x;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100U);
  EXPECT_EQ(r.regions, 1U);
  EXPECT_NEAR(r.max_thickness_mm, floor_rest(1), 0.01);  // at the fillet's foot: 0.6056
  EXPECT_NEAR(r.axis_deg, 90, 1);                        // along the corner (Y)
  // The wall's rest ends where the Ø6 touches it, 3 − √(6t + t²) = 2.653 (within a cell's envelope).
  EXPECT_NEAR(r.rest_top_z, kBandEnd, 0.15);
  // The outline: the band grown by the margin (r/2 = 0.5 mm) within a cell.
  const Boundary& b = r.boundary;
  for (double x : {1.0, 1.5, 2.0, 2.6, kBandEnd + 0.5 - r.cell}) EXPECT_TRUE(b.encloses(x, 15)) << x;
  for (double x : {0.5 - 2 * r.cell, kBandEnd + 0.5 + 2 * r.cell, 5.0, -3.0}) EXPECT_FALSE(b.encloses(x, 15)) << x;
}

TEST(RestFinishing, CleansTheBandOnlyAndNeverGouges) {
  const ingest::Mesh part = l_corner();
  const DropCutter two(part, Cutter::ball(2));
  const RestRegions r = behind_six(part, two);
  const FinishPlan plan = plan_rest(part, two, r, Cutter::ball(6).describe(), rest_params());
  ASSERT_FALSE(plan.passes.empty());
  // Every CL point: within the band plus the margin and the cell, below the rest's top, no gouge
  // (the ball's centre at least R from every triangle), and sampled every 0.1 mm for coverage.
  std::vector<Eigen::Vector3d> centres;
  for (const Pass& pass : plan.passes)
    for (std::size_t q = 0; q < pass.points.size(); ++q) {
      const Eigen::Vector3d& p = pass.points[q];
      // Cut to where the rest is (over half the threshold at the contact: the floor up to
      // 3 − √(6ε + ε²) = 2.755), run on by R/8 along the pass: no pass over the bare floor beyond.
      EXPECT_GE(p.x(), 0.5 - 2 * r.cell) << p.transpose();
      EXPECT_LE(p.x(), kTouched + tol::rest_run_on_radii * 1.0 + 2 * r.cell) << p.transpose();
      EXPECT_LE(p.z(), r.rest_top_z + 1e-9);
      if (q == 0) continue;
      const Eigen::Vector3d& a = pass.points[q - 1];
      const int n = std::max(1, static_cast<int>(std::ceil((p - a).norm() / 0.1)));
      for (int k = 0; k < n; ++k) centres.push_back(a + (p - a) * (k + 0.5) / n + Eigen::Vector3d(0, 0, 1));
    }
  ASSERT_GT(centres.size(), 1000U);
  double worst = HUGE_VAL;
  for (const Eigen::Vector3d& c : centres)
    if (c.y() > 12 && c.y() < 18) worst = std::min(worst, distance_to_mesh(part, c));
  EXPECT_GE(worst, 1 - 1e-4) << "the Ø2 ball goes into the part by " << 1 - worst << " mm";
  // Coverage at y = 15: floor, fillet and wall points of the band are within the threshold of the
  // Ø2's surface at some sampled position (a ball: |P − centre| − 1).
  std::vector<Eigen::Vector3d> band;
  for (double x = 1.05; x < kBandEnd - 0.05; x += 0.1) band.emplace_back(x, 15, 0);
  for (double t = 0.05; t < 0.5 * std::numbers::pi; t += 0.1) band.emplace_back(1 - std::cos(t), 15, 1 - std::sin(t));
  for (double z = 1.05; z < kBandEnd - 0.05; z += 0.1) band.emplace_back(0, 15, z);
  for (const Eigen::Vector3d& p : band) {
    double d = HUGE_VAL;
    for (const Eigen::Vector3d& c : centres)
      if (std::abs(c.y() - 15) < 1.2) d = std::min(d, (p - c).norm() - 1);
    EXPECT_LE(d, kT) << "rest left at " << p.transpose();
  }
}

TEST(RestFinishing, LinksClearWhatTheReferenceLeftAndEntriesComeDownJustAboveIt) {
  const ingest::Mesh part = l_corner();
  const DropCutter two(part, Cutter::ball(2));
  const RestRegions r = behind_six(part, two);
  ASSERT_TRUE(r.stock_tip);
  // Over the floor beyond the corner the stock is the floor (the Ø6 reached it); in the corner the
  // Ø2 must stand at least on the Ø6's arc: at x = 1 (the Ø2 against the wall) the arc is at
  // 3 − √(9 − 2²) = 0.764 at x = 1 and rises toward the wall.
  EXPECT_NEAR(r.stock_tip(8, 15), kT, 0.01);
  EXPECT_GE(r.stock_tip(1.0, 15), 3 - std::sqrt(5.0));
  const FinishPlan plan = plan_rest(part, two, r, Cutter::ball(6).describe(), rest_params());
  gcode::Point3 at{0, 0, 0};
  std::size_t plunges = 0;
  for (const auto& item : plan.program.items) {
    const auto* m = std::get_if<gcode::Move>(&item);
    if (m == nullptr) continue;
    const bool across = std::hypot(m->to[0] - at[0], m->to[1] - at[1]) > 1e-9;
    if (m->motion == gcode::Motion::Rapid && across && at[2] < 20 - 1e-9) {  // a link (not from safe Z)
      for (double f = 0; f <= 1; f += 0.01) {
        const double x = at[0] + f * (m->to[0] - at[0]), y = at[1] + f * (m->to[1] - at[1]);
        EXPECT_GE(m->to[2], r.stock_tip(x, y) + 0.5) << "a rapid into the stock at " << x << ", " << y;
      }
    }
    if (m->motion == gcode::Motion::Line && !across && m->to[2] < at[2]) {  // an entry's plunge
      ++plunges;
      EXPECT_NEAR(at[2], std::max(m->to[2], r.stock_tip(m->to[0], m->to[1])) + 0.1, 1e-9);
    }
    at = m->to;
  }
  EXPECT_EQ(plunges, plan.lifts + 1);
}

// Over a stock a short link stays down only when that is the quicker: two passes on a floor either
// side of a ridge 2 mm high (x 4.5 … 5.5, y along), 3 mm apart — the stay-down link climbs over it
// (about 5 mm of feed), the lift rises to the ridge's top plus the 1 mm clearance at rapid (5000
// mm/min, 500 mm/s²), crosses and comes down (≈ 0.5 s). At 300 mm/min the climb takes > 1 s: it
// lifts; at 3000 mm/min it stays down; without a stock (the strategies) it stays down as before.
/// A stock of n × n cells (n × rows, given rows) of `cell` from the centre (x0, y0) whose height
/// depends on x only.
template <class Height>
RestStock stock_along_x(double cell, double x0, double y0, int n, Height height, int rows = 0) {
  RestStock st;
  st.cell = cell, st.x0 = x0, st.y0 = y0, st.nx = n, st.ny = rows > 0 ? rows : n;
  st.z.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(st.ny));
  for (int i = 0; i < st.ny; ++i)
    for (int j = 0; j < n; ++j)
      st.z[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] =
          height(x0 + cell * j);
  return st;
}

TEST(RestFinishing, OverAStockALinkLiftsWhenThatIsQuickerThanFeedingOverARidge) {
  const ingest::Mesh part = extruded({{-5, 0}, {4.5, 0}, {5, 2}, {5.5, 0}, {15, 0}}, 30);
  const DropCutter two(part, Cutter::ball(2));
  FinishPlan plan;
  plan.strategy = Strategy::SlopeMode;
  plan.passes.resize(2);
  plan.passes[0].points = {{1, 15, 0}, {3.5, 15, 0}};
  plan.passes[1].points = {{6.5, 15, 0}, {9, 15, 0}};
  auto linked = [&](double feed, bool stock) {
    FinishParams p = rest_params();
    p.feed_mm_min = feed;
    if (stock) p.stock_tip = [](double, double) { return -HUGE_VAL; };
    FinishPlan q = plan;
    detail::relink(part, two, p, q);
    return q;
  };
  const FinishPlan slow = linked(300, true), fast = linked(3000, true), strategy = linked(300, false);
  EXPECT_EQ(slow.lifts, 1U);
  EXPECT_EQ(fast.lifts, 0U);
  EXPECT_EQ(strategy.lifts, 0U);
  // The lift crosses at the ridge's top plus the clearance (the ball's tip rides 2 mm up at the
  // ridge's apex), and the program is the quicker for it by the machine's own planner.
  double crossing = -HUGE_VAL;
  gcode::Point3 at{0, 0, 0};
  for (const auto& item : slow.program.items)
    if (const auto* m = std::get_if<gcode::Move>(&item)) {
      if (m->motion == gcode::Motion::Rapid && std::abs(m->to[0] - at[0]) > 1) crossing = m->to[2];
      at = m->to;
    }
  EXPECT_NEAR(crossing, 3.0, 1e-6);
  FinishPlan stayed = plan;
  FinishParams p = rest_params();
  p.feed_mm_min = 300;
  p.stock_tip = [](double, double) { return -HUGE_VAL; };
  p.motion.acceleration_mm_s2 = 1e-3;  // rapids crawl: the link stays down, the same passes
  detail::relink(part, two, p, stayed);
  EXPECT_EQ(stayed.lifts, 0U);
  EXPECT_LT(gcode::stats(slow.program, {}).kinematic_time_min, gcode::stats(stayed.program, {}).kinematic_time_min);
}

// A flat floor (z = 0) with 0.05 mm of rest over x in [1, 3.5] and [6.5, 9], clean between, and
// two pieces along y = 15 over the rest joined by a 3 mm stay-down link. A Ø2 ball on the floor
// takes the rest from √(2 · 0.05 − 0.05²) = 0.312 mm off its axis, so the link feeds through air
// from x = 3.5 (the first piece's end took all it reaches there) to 6.5 − 0.312 = 6.19: 2.69 mm,
// in moves of 0.1 mm. With the stock's cut known to the linking that run is hopped, and
// by an oracle replaying the program on the stock: the feed through air is under the hop's
// threshold, no rapid cuts, and the rest left is what feeding through leaves.
TEST(RestFinishing, AStayDownLinkHopsOverTheAirBetweenTwoPatchesOfRest) {
  const ingest::Mesh part = extruded({{-5, 0}, {15, 0}}, 30);
  const DropCutter two(part, Cutter::ball(2));
  const Cutter ball = Cutter::ball(2);
  const auto stock = [] {
    return stock_along_x(
        0.02, -4.99, 13.01, 1000, [](double x) { return (x >= 1 && x <= 3.5) || (x >= 6.5 && x <= 9) ? 0.05 : 0.0; },
        200);
  };
  FinishPlan plan;
  plan.strategy = Strategy::SlopeMode;
  plan.passes.resize(2);
  plan.passes[0].points = {{1, 15, 0}, {3.5, 15, 0}};
  plan.passes[1].points = {{6.5, 15, 0}, {9, 15, 0}};
  const auto linked = [&](bool known) {
    FinishParams p = rest_params();
    p.feed_mm_min = 3000;  // quicker staying down than lifting
    p.stock_tip = [](double, double) { return -HUGE_VAL; };
    auto st = std::make_shared<RestStock>(stock());
    p.stock_cut = [st, ball](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { st->cut(ball, a, b); };
    if (known)
      p.stock_cut_depth = [st, ball](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return st->cut_depth(ball, a, b);
      };
    FinishPlan q = plan;
    detail::relink(part, two, p, q);
    return q;
  };
  struct Replayed {
    double air_mm = 0, rapid_cut_mm = 0, longest_plunge_mm = 0;
    RestStock left;
  };
  const auto replay = [&](const gcode::Program& program) {
    Replayed r{0, 0, 0, stock()};
    gcode::Point3 at{0, 0, 20};
    bool after_rapid = false;
    for (const auto& item : program.items) {  // O(moves · placements)
      const auto* m = std::get_if<gcode::Move>(&item);
      if (m == nullptr) continue;
      const Eigen::Vector3d a(at[0], at[1], at[2]), b(m->to[0], m->to[1], m->to[2]);
      const double cut = r.left.cut_depth(ball, a, b);
      if (m->motion == gcode::Motion::Rapid)
        r.rapid_cut_mm = std::max(r.rapid_cut_mm, cut);
      else if (cut < tol::rest_air_cut_mm)
        r.air_mm += (b - a).norm();
      if (m->motion != gcode::Motion::Rapid && after_rapid && a.x() > 2)  // a plunge, past the entry
        r.longest_plunge_mm = std::max(r.longest_plunge_mm, (b - a).norm());
      after_rapid = m->motion == gcode::Motion::Rapid;
      r.left.cut(ball, a, b);
      at = m->to;
    }
    return r;
  };
  const FinishPlan fed = linked(false), hopped = linked(true);
  EXPECT_EQ(fed.hops, 0U);
  EXPECT_EQ(fed.lifts, 0U);
  EXPECT_EQ(hopped.hops, 1U);
  EXPECT_EQ(hopped.lifts, 1U);
  const Replayed f = replay(fed.program), h = replay(hopped.program);
  EXPECT_GT(f.air_mm, 2.55);
  EXPECT_LT(f.air_mm, 2.75);
  EXPECT_LT(h.air_mm, tol::rest_air_hop_radii * 1.0);
  EXPECT_EQ(f.rapid_cut_mm, 0.0);
  EXPECT_EQ(h.rapid_cut_mm, 0.0);
  // The hop comes down into the rest at the second patch through the approach and the 0.05 mm there.
  EXPECT_GT(h.longest_plunge_mm, tol::rest_approach_mm);
  EXPECT_LE(h.longest_plunge_mm, tol::rest_approach_mm + 0.05 + 1e-9);
  double higher = 0, on_the_line = 0;
  for (std::size_t c = 0; c < h.left.z.size(); ++c) {  // O(cells)
    higher = std::max(higher, h.left.z[c] - f.left.z[c]);
    if (std::abs(h.left.y0 + h.left.cell * static_cast<double>(c / 1000) - 15) < 0.1)
      on_the_line = std::max(on_the_line, h.left.z[c]);
  }
  EXPECT_LT(higher, 1e-3);
  EXPECT_LT(on_the_line, 0.006);  // the ball's profile 0.1 mm off its axis: 0.005 mm
}

/// The stock the Ø6 ball leaves on the L corner, by hand, on a z-map grid (cells of 0.02 mm,
/// centres at multiples of 0.02 + 0.01): over the top (x < 0) z = 10; in the corner the Ø6's lower
/// arc about (3, 3), z = 3 − √(9 − (3 − x)²) for 0 < x < 3; the floor z = 0 beyond.
RestStock six_stock() {
  return stock_along_x(0.02, -9.99, 0.01, 1500, [](double x) {
    return x < 0 ? 10.0 : x < 3 ? 3 - std::sqrt(9 - (3 - x) * (3 - x)) : 0.0;
  });
}

TEST(RestStock, TheToolClearsTheHighestCellWithinReachLessItsProfileThere) {
  // Flat at z = 1 (cells of 0.1), one column at z = 3 whose centre is 0.5 mm from the axis at
  // (1, 1) and one at z = 9 out of the Ø2 ball's reach from there.
  RestStock st;
  st.cell = 0.1, st.x0 = 0, st.y0 = 0, st.nx = 25, st.ny = 21;
  st.z.assign(25 * 21, 1.0);
  st.z[10 * 25 + 15] = 3.0;  // (1.5, 1.0)
  st.z[10 * 25 + 21] = 9.0;  // (2.1, 1.0): 1.1 mm away, beyond R plus half a diagonal
  const Cutter ball = Cutter::ball(2);
  // The column at 0.5 taken at its corner nearest the axis, 0.5 − 0.1·√2/2: the ball is
  // 1 − √(1 − d²) above its tip there.
  const double d = 0.5 - 0.1 * std::numbers::sqrt2 / 2;
  EXPECT_NEAR(st.clearing_tip(ball, 1.0, 1.0), 3 - (1 - std::sqrt(1 - d * d)), 1e-12);
  EXPECT_NEAR(st.clearing_tip(Cutter::flat(2), 1.0, 1.0), 3.0, 1e-12);  // flat: no rise
  const double far = 0.9 - 0.1 * std::numbers::sqrt2 / 2;               // from (1.2, 1) to the far column
  EXPECT_NEAR(st.clearing_tip(ball, 1.2, 1.0), 9.0 - (1 - std::sqrt(1 - far * far)), 1e-12);
  st.z_offset = -0.5;
  EXPECT_NEAR(st.clearing_tip(ball, 0.5, 0.5), 0.5, 1e-12);  // only the flat cells within reach, shifted
  EXPECT_EQ(st.clearing_tip(ball, 40, 40), -HUGE_VAL);       // off the grid: nothing to clear
}

TEST(RestStock, TheMaterialIsTheStocksHeightOverThePointAlongTheNormal) {
  RestStock st;
  st.cell = 0.5, st.x0 = 0, st.y0 = 0, st.nx = 9, st.ny = 3;
  for (int i = 0; i < st.ny; ++i)
    for (int j = 0; j < st.nx; ++j) st.z.push_back(0.1 * st.cell * j + 1);  // z = 0.1·x + 1: bilinear is exact
  st.check();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(st.height(1.3, 0.7), 1.13, 1e-12);
  EXPECT_NEAR(st.material({1.3, 0.7, 0.0}, up), 1.13, 1e-4);
  // Along a normal tilted 60° from Z towards +X: 1.13 − 0.5 + 0.1·t·sin60 = t·cos60 ⇒ t = 0.63 / (0.5 − 0.0866),
  // less half a cell times the normal's horizontal part (where a wall stands in a cell is not known).
  const double s60 = std::sin(std::numbers::pi / 3);
  const Eigen::Vector3d tilted(s60, 0, std::cos(std::numbers::pi / 3));
  EXPECT_NEAR(st.material({1.3, 0.7, 0.5}, tilted), 0.63 / (0.5 - 0.1 * s60) - 0.25 * s60, 1e-4);
  EXPECT_EQ(st.material({1.3, 0.7, 2.0}, up), 0.0);  // above the stock: none
  EXPECT_EQ(st.material({4.1, 0.7, 0.0}, up), 0.0);  // off the grid: air
  // A wall facing +X at x = 1.3, z = 0: the stock beside it (never below z = 1) ends with the grid at x = 4.
  EXPECT_NEAR(st.material({1.3, 0.7, 0.0}, Eigen::Vector3d::UnitX()), 2.7 - 0.25, 1e-4);
  RestStock bad = st;
  bad.z.pop_back();
  EXPECT_THROW(bad.check(), Error);
  bad = st;
  bad.z[3] = std::nan("");
  EXPECT_THROW(bad.check(), Error);
}

// The exact measures (RestStock::exact_mm) decide where the nearest cell's design point lies on
// the point's tangent plane within half a cell; elsewhere the stock's reading stands.
TEST(RestStock, AnExactMeasureDecidesOnItsOwnSurfaceOnly) {
  RestStock st;
  st.cell = 0.5, st.x0 = 0, st.y0 = 0, st.nx = 9, st.ny = 3;
  st.z.assign(27, 1.0);  // flat stock at z = 1 (grid frame)
  st.z_offset = -0.25;   // at z = 0.75 in the part's frame
  st.exact_mm.assign(27, std::numeric_limits<float>::quiet_NaN());
  st.exact_z.assign(27, std::numeric_limits<double>::quiet_NaN());
  const std::size_t c = 1 * 9 + 3;  // the cell at (1.5, 0.5)
  st.exact_mm[c] = 0.03f;
  st.exact_z[c] = 0.95;  // its design point at z = 0.70 in the part's frame
  st.check();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // A floor point near the cell centre, on the design point's plane: the exact figure, whatever the stock reads.
  EXPECT_NEAR(st.material({1.6, 0.4, 0.70}, up), 0.03, 1e-7);
  EXPECT_NEAR(st.material_over({1.4, 0.6, 0.70}, up, 0.02), 0.03, 1e-7);
  EXPECT_NEAR(st.material({1.6, 0.4, 0.90}, up), 0.03, 1e-7);  // 0.2 off the plane: within half a cell
  // Off that plane by more than half a cell (another surface in the column): the stock's height over it.
  EXPECT_NEAR(st.material({1.6, 0.4, 0.2}, up), 0.55, 1e-4);
  // A wall facing +X through the design point: on its plane whatever its height.
  EXPECT_NEAR(st.material({1.5, 0.5, 0.1}, Eigen::Vector3d::UnitX()), 0.03, 1e-7);
  // The neighbouring cell, measured nowhere: the stock's reading.
  EXPECT_NEAR(st.material({2.0, 0.5, 0.70}, up), 0.05, 1e-4);
  RestStock bad = st;
  bad.exact_z.pop_back();
  EXPECT_THROW(bad.check(), Error);
  bad = st;
  bad.exact_mm.clear(), bad.exact_z.clear();
  EXPECT_NO_THROW(bad.check());
  EXPECT_NEAR(bad.material({1.6, 0.4, 0.70}, up), 0.05, 1e-4);
}

TEST(RestStock, EngagementAndCutAreTheToolsProfileOverTheCells) {
  // Flat at z = 1 on cells of 0.05 (centres at multiples of 0.05): a Ø1 ball with its tip at 0
  // meets all 1 mm of it; at 0.8, where 1 > 0.8 + 0.5 − √(0.25 − d²), i.e. d < 0.4: 0.2 mm.
  RestStock st;
  st.cell = 0.05, st.x0 = 0, st.y0 = 0, st.nx = 81, st.ny = 41;
  st.z.assign(81 * 41, 1.0);
  const Cutter ball = Cutter::ball(1);
  EXPECT_NEAR(st.engagement(ball, 1, 1, 0.0), 1.0, 1e-12);
  EXPECT_NEAR(st.engagement(ball, 1, 1, 0.8), 0.2, 1e-12);
  EXPECT_EQ(st.engagement(ball, 1, 1, 1.0), 0.0);
  // Swept from (1, 1) to (3, 1) at tip 0.8: the cells on the line at 0.8, 0.3 aside at
  // 0.8 + 0.5 − 0.4 = 0.9, 0.35 aside at 1.3 − √(0.25 − 0.1225); from 0.4 aside (where the ball's
  // surface reaches z 1) untouched.
  st.cut(ball, {1, 1, 0.8}, {3, 1, 0.8});
  auto at = [&](double x, double y) {
    return st.z[static_cast<std::size_t>(std::lround(y / 0.05)) * 81 + static_cast<std::size_t>(std::lround(x / 0.05))];
  };
  EXPECT_NEAR(at(2, 1), 0.8, 1e-12);
  EXPECT_NEAR(at(2, 1.3), 0.9, 1e-12);
  EXPECT_NEAR(at(2, 1.35), 1.3 - std::sqrt(0.25 - 0.35 * 0.35), 1e-12);
  EXPECT_EQ(at(2, 1.45), 1.0);
  EXPECT_EQ(at(3.6, 1), 1.0);
  // The same sweep again would cut nothing; 0.1 lower, 0.1 mm (the stock the same ball's surface
  // left, 0.1 under it), and the stock is kept.
  EXPECT_EQ(st.cut_depth(ball, {1, 1, 0.8}, {3, 1, 0.8}), 0.0);
  EXPECT_NEAR(st.cut_depth(ball, {1, 1, 0.7}, {3, 1, 0.7}), 0.1, 1e-12);
  EXPECT_NEAR(at(2, 1), 0.8, 1e-12);
  // 0.1 lower over the line: the cells the sweep left at 1 from 0.4 to √(0.25 − 0.2²) = 0.458 aside
  // stand over the lower ball, 0.3 above its tip (its flank meets them first).
  EXPECT_NEAR(st.engagement(ball, 2, 1, 0.7), 0.3, 1e-12);
  st.z_offset = 0.5;  // heights read 0.5 higher
  EXPECT_NEAR(st.engagement(ball, 2, 1, 1.2), 0.3, 1e-12);
}

// What a tool takes off is the most a cell stands above its surface, not how high above its tip
// the cell stands: a cell grazed at the ball's rim is a hair's cut however tall (issue 41's air).
TEST(RestStock, RemovalIsTheMostACellStandsAboveTheToolsSurface) {
  RestStock st;
  st.cell = 0.05, st.x0 = 0, st.y0 = 0, st.nx = 81, st.ny = 41;
  st.z.assign(81 * 41, 0.0);
  const Cutter ball = Cutter::ball(1);
  // One column 1 mm tall at (1.45, 1): 0.45 from a tip at (1, 1, 0), where the ball's surface stands
  // 0.5 − √(0.25 − 0.45²) = 0.28206 high: it takes 0.71794 off, the flutes meet it 1 mm up.
  st.z[20 * 81 + 29] = 1.0;
  const double surface = 0.5 - std::sqrt(0.25 - 0.45 * 0.45);
  EXPECT_NEAR(st.removal(ball, 1, 1, 0.0).height, 1.0 - surface, 1e-12);
  EXPECT_NEAR(st.engagement(ball, 1, 1, 0.0), 1.0, 1e-12);
  // Normal to the ball's surface it takes the column's reach past the rim: it stands above the
  // centre (z 0.5), so R − 0.45 = 0.05 — a wall's scallop is measured across the wall.
  EXPECT_NEAR(st.removal(ball, 1, 1, 0.0).thickness, 0.05, 1e-12);
  // A tip 0.7 up: the column stands 0.01794 over the surface — the engagement still reads 0.3;
  // its top 0.2 below the centre, 0.5 − √(0.45² + 0.2²) = 0.0075565 into the ball.
  EXPECT_NEAR(st.removal(ball, 1, 1, 0.7).height, 0.3 - surface, 1e-12);
  EXPECT_NEAR(st.removal(ball, 1, 1, 0.7).thickness, 0.5 - std::hypot(0.45, 0.2), 1e-12);
  EXPECT_NEAR(st.engagement(ball, 1, 1, 0.7), 0.3, 1e-12);
  EXPECT_EQ(st.removal(ball, 1, 1, 1.0 - surface).height, 0.0);
  EXPECT_EQ(st.removal(ball, 1, 1, 1.0 - surface).thickness, 0.0);
  st.z_offset = 0.5;
  EXPECT_NEAR(st.removal(ball, 1, 1, 1.2).height, 0.3 - surface, 1e-12);
  // A bull nose (Ø1, corner 0.2: flat to 0.3 from the axis) at tip 0: the column is 0.15 out from
  // its corner's centre circle, above the corner, so 0.2 − 0.15 = 0.05 into it; the corner stands
  // 0.2 − √(0.2² − 0.15²) = 0.067712 high there. A column 0.3 tall under the flat (0.1 from the
  // axis) reaches 0.3 into it, the height it stands over the flat.
  st.z_offset = 0;
  const Cutter bull = Cutter::bull(1, 0.2);
  EXPECT_NEAR(st.removal(bull, 1, 1, 0.0).height, 1.0 - (0.2 - std::sqrt(0.04 - 0.0225)), 1e-12);
  EXPECT_NEAR(st.removal(bull, 1, 1, 0.0).thickness, 0.05, 1e-12);
  st.z[20 * 81 + 29] = 0.0;
  st.z[20 * 81 + 22] = 0.3;
  EXPECT_NEAR(st.removal(bull, 1, 1, 0.0).height, 0.3, 1e-12);
  EXPECT_NEAR(st.removal(bull, 1, 1, 0.0).thickness, 0.3, 1e-12);
}

// removal_behind is removal on the stock as the placements before leave it: against a copy cut by
// them (RestStock::cut of a point), on a bumpy stock, at random placements (fixed seed).
TEST(RestStock, RemovalBehindPlacementsIsRemovalOnTheStockTheyLeave) {
  RestStock st;
  st.cell = 0.05, st.x0 = 0, st.y0 = 0, st.nx = 61, st.ny = 61;
  st.z.resize(61 * 61);
  for (int i = 0; i < 61; ++i)
    for (int j = 0; j < 61; ++j)
      st.z[static_cast<std::size_t>(i * 61 + j)] = 0.3 + 0.2 * std::sin(0.4 * i) * std::cos(0.3 * j);
  const Cutter ball = Cutter::ball(1);
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> xy(1.0, 2.0), zz(0.0, 0.4);
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<Eigen::Vector3d> before;
    for (int k = 0; k < trial % 6; ++k) before.emplace_back(xy(rng), xy(rng), zz(rng));
    const Eigen::Vector3d p(xy(rng), xy(rng), zz(rng));
    RestStock cut = st;
    for (const Eigen::Vector3d& q : before) cut.cut(ball, q, q);
    const Removal behind = st.removal_behind(ball, p, before.data(), before.size()),
                  after = cut.removal(ball, p.x(), p.y(), p.z());
    EXPECT_NEAR(behind.height, after.height, 1e-12);
    EXPECT_NEAR(behind.thickness, after.thickness, 1e-12);
  }
}

namespace {
/// The L corner's stock with a 4 mm-tall skin left along the wall's foot (x < 1.5, z = 4: what a
/// roughing with a large stock to leave leaves), on cells of 0.05.
RestStock skin_stock() {
  RestStock st;
  st.cell = 0.05, st.x0 = -4.975, st.y0 = 0.025, st.nx = 300, st.ny = 600;
  st.z.resize(static_cast<std::size_t>(st.nx) * static_cast<std::size_t>(st.ny));
  for (int i = 0; i < st.ny; ++i)
    for (int j = 0; j < st.nx; ++j) {
      const double x = st.x0 + st.cell * j;
      st.z[static_cast<std::size_t>(i) * static_cast<std::size_t>(st.nx) + static_cast<std::size_t>(j)] = x < 0 ? 10.0
                                                                                                          : x < 1.5
                                                                                                              ? 4.0
                                                                                                              : 0.0;
    }
  return st;
}

/// The deepest cut of a program's feed moves on `stock` (machined move by move, each probed every
/// 0.025 mm before it cuts there), mesh frame = program frame.
double deepest_cut(const gcode::Program& program, RestStock stock, const Cutter& tool) {
  double most = 0;
  Eigen::Vector3d at(0, 0, 1e3);
  for (const gcode::Item& item : program.items) {  // O(moves · length / 0.025 · (R / cell)²)
    const auto* m = std::get_if<gcode::Move>(&item);
    if (m == nullptr) continue;
    const Eigen::Vector3d to(m->to[0], m->to[1], m->to[2]);
    if (m->motion != gcode::Motion::Rapid) {
      const int n = std::max(1, static_cast<int>(std::ceil((to - at).norm() / 0.025)));
      for (int k = 1; k <= n; ++k) {
        const Eigen::Vector3d a = at + (to - at) * ((k - 1.0) / n), b = at + (to - at) * (static_cast<double>(k) / n);
        most = std::max(most, stock.engagement(tool, b.x(), b.y(), b.z()));
        stock.cut(tool, a, b);
      }
    }
    at = to;
  }
  return most;
}
}  // namespace

// A rest that stands taller than the tool's flutes (a 4 mm skin at the wall's foot, a Ø2 ball
// with 1.5 mm of flutes) is taken from the top down, in steps of the flutes less the ball's
// radius (what a step leaves against the wall stands that much over the next): no move of the
// program — passes, raised copies and links — cuts deeper than the flutes (replayed on the stock);
// the same tool with no stated flutes plans the pass alone, which meets the skin's whole height.
// (Steps of 2/3 of the flutes met 1.78 mm here.)
TEST(RestFinishing, ARestTallerThanTheFlutesIsSteppedDownFromTheTop) {
  const ingest::Mesh part = l_corner();
  const RestStock stock = skin_stock();
  Cutter tool = Cutter::ball(2);
  tool.flute_length_mm = 1.5;
  FinishParams p = rest_params();
  p.step_down_mm = 0.25;
  p.stepover_mm = 0.25;
  auto plan_with = [&](const Cutter& c) {
    const DropCutter dc(part, c);
    RestParams rp;
    rp.threshold_mm = kT;
    rp.stock = &stock;
    const RestRegions r = rest_regions(part, dc, rp, -5, 0, 10, 30);
    FinishParams q = p;
    q.tool = c;
    return plan_rest(part, dc, r, "the skin", q);
  };
  const FinishPlan stepped = plan_with(tool);
  EXPECT_NE(stepped.program.header.back().find("stepped down from the top"), std::string::npos)
      << stepped.program.header.back();
  EXPECT_LE(deepest_cut(stepped.program, stock, tool), 1.5);
  Cutter unstated = tool;
  unstated.flute_length_mm = 0;
  EXPECT_GT(deepest_cut(plan_with(unstated).program, stock, tool), 3.0);
}

TEST(RestRegions, FromTheStockTheSixMillimetreBallLeftTheBandIsTheHandComputedOne) {
  const ingest::Mesh part = l_corner();
  const DropCutter two(part, Cutter::ball(2));
  const RestStock stock = six_stock();
  RestParams rp;
  rp.threshold_mm = kT;
  rp.stock = &stock;
  rp.reference = Cutter::ball(1);  // not used from the stock (a smaller one would be refused)
  const RestRegions r = rest_regions(part, two, rp, -10, 0, 20, 30);
  EXPECT_NEAR(r.cell, rest_cell_mm(Cutter::ball(2), kT), 1e-12);
  std::size_t checked = 0;
  for (int i = 0; i < r.ny; ++i) {
    const double y = r.y0 + r.cell * i;
    if (y < 1 || y > 29) continue;
    for (int j = 0; j < r.nx; ++j) {
      const double x = r.x0 + r.cell * j;
      const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(r.nx) + static_cast<std::size_t>(j);
      if (std::abs(x - 1) < r.cell || std::abs(x - kBandEnd) < r.cell) continue;
      const bool in_band = x > 1 && x < kBandEnd;
      EXPECT_EQ(r.mask[k] == 1 || (r.mask[k] == 2 && r.thickness[k] > kT), in_band) << x << " " << y;
      if (in_band) {  // vertical stock over the floor under the Ø2, 3 − √(9 − (3 − x)²): the most of the
        // node's contact and of the design samples its cell gathers (within half a cell nearer the corner)
        auto stock_at = [](double u) { return 3 - std::sqrt(9 - (3 - u) * (3 - u)); };
        EXPECT_GE(r.thickness[k], stock_at(x) - 0.002) << x;
        EXPECT_LE(r.thickness[k], stock_at(x - r.cell / 2) + 0.002) << x;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 500U);
  EXPECT_EQ(r.regions, 1U);
  EXPECT_NEAR(r.rest_top_z, kBandEnd, 0.15);  // where the wall's rest ends (stock beside it thinner than t)
  ASSERT_TRUE(r.material);
  EXPECT_NEAR(r.material({2, 15, 0}, Eigen::Vector3d::UnitZ()), 3 - std::sqrt(8.0), 1e-3);
  // The wall's rest beside the point (0, 15, 2.6): where the Ø6's arc comes down to z = 2.6, less
  // half a cell (a wall's place in the columns is known to that).
  EXPECT_NEAR(r.material({0, 15, 2.6}, Eigen::Vector3d::UnitX()), 3 - std::sqrt(9 - 0.4 * 0.4) - 0.01, 1e-3);
  // Its rest program stays where the stock is: within the band plus the R/8 run-on and the cell.
  const FinishPlan plan = plan_rest(part, two, r, "the stock", rest_params());
  ASSERT_FALSE(plan.passes.empty());
  for (const Pass& pass : plan.passes)
    for (const Eigen::Vector3d& p : pass.points) {
      EXPECT_GE(p.x(), 0.5 - 2 * r.cell) << p.transpose();
      EXPECT_LE(p.x(), kTouched + tol::rest_run_on_radii * 1.0 + 2 * r.cell) << p.transpose();
    }
}

TEST(RestRegions, TheUnreachableAreaOfABallInTheCornerIsTheHandComputedBand) {
  // The Ø6 cannot come within t of the floor for 0 < x < 3 − √(6t + t²) nor of the wall below that
  // height (no XY area), nor of the fillet (x in [0, 1]): over y in [0, 30], less the open ends
  // where it comes in from the side (up to 3 mm each end), the XY band is 2.653 mm wide.
  const ingest::Mesh part = l_corner();
  const RestRegions u = unreachable_regions(part, Cutter::ball(6), kT);
  double area = 0;
  for (int i = 0; i < u.ny; ++i) {
    const double y = u.y0 + u.cell * i;
    if (y < 8 || y > 22) continue;
    for (int j = 0; j < u.nx; ++j)
      if (u.mask[static_cast<std::size_t>(i) * static_cast<std::size_t>(u.nx) + static_cast<std::size_t>(j)] != 0)
        area += u.cell;  // per row: the band's width
  }
  const double rows = std::floor(22 / u.cell) - std::ceil(8 / u.cell) + 1;
  EXPECT_NEAR(area / rows, kBandEnd, 2 * u.cell);
  EXPECT_LT(unreachable_area_mm2(part, Cutter::ball(2), kT), unreachable_area_mm2(part, Cutter::ball(6), kT));
}

// Z-levels into an inside corner: a 10 mm high plate with its quadrant x > 4.12, y > 4.13 cut
// down to a floor at 0 (two vertical walls meeting in a concave corner, off the 0.25 mm grid the
// levels are seeded on). At z = 5 a Ø1 ball's centre must keep 0.5 from both walls: its level
// turns a sharp corner at (4.62, 4.63), inside the seed grid's cell [4.5, 4.75]², whose crossings
// (4.62, 4.75) and (4.75, 4.63) a chord would join 0.088 mm off the corner, on the air side —
// leaving the corner's rest. Rest finishing's levels (into_corners) reach it within the chord
// tolerance; no point of any level lies inside the walls' offset (no gouge).
TEST(RestFinishing, ZLevelsReachIntoAnInsideCornerBetweenTheirSeedGridsNodes) {
  const double cx = 4.12, cy = 4.13, R = 0.5;
  ingest::Mesh m;
  m.V.resize(14, 3);
  m.V << 0, 0, 10, cx, 0, 10, cx, 10, 10, 0, 10, 10,  // the top, x < cx
      cx, 0, 10, 10, 0, 10, 10, cy, 10, cx, cy, 10,   // the top, y < cy
      cx, cy, 0, 10, cy, 0, 10, 10, 0, cx, 10, 0,     // the floor
      cx, 10, 10, 10, cy, 10;                         // the walls' far top corners
  m.F.resize(10, 3);
  m.F << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11, 8, 11, 12, 8, 12,
      7,                   // the wall x = cx (y from cy to 10)
      8, 7, 13, 8, 13, 9;  // the wall y = cy (x from cx to 10)
  const DropCutter ball(m, Cutter::ball(2 * R));
  const detail::Sampler s(m, ball);
  FinishParams p = rest_params();
  p.step_down_mm = 2.5;
  p.chord_tolerance_mm = 0.005;
  const detail::Box box{0, 0, 10, 10};
  const Eigen::Vector2d corner(cx + R, cy + R);
  for (const bool into : {false, true}) {
    double nearest = HUGE_VAL, deepest = 0;
    for (const auto& level : detail::waterline_loops(s, box, p, into))
      for (const auto& loop : level)
        for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
          const Eigen::Vector3d &a = loop[k].p, &b = loop[k + 1].p;
          if (std::abs(a.z() - 5) > 1e-9 || std::abs(b.z() - 5) > 1e-9) continue;
          const Eigen::Vector2d ab = (b - a).head<2>();
          const double t = std::clamp((corner - a.head<2>()).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
          nearest = std::min(nearest, (a.head<2>() + t * ab - corner).norm());
          if (a.x() > cx && a.y() > cy) deepest = std::max(deepest, std::max(cx + R - a.x(), cy + R - a.y()));
        }
    EXPECT_LE(deepest, 1e-3) << "a level point inside the walls' offset";
    if (into)
      EXPECT_LE(nearest, p.chord_tolerance_mm + 1e-3);
    else
      EXPECT_GT(nearest, 0.05);  // the seed grid's chord (what the five strategies keep)
  }
}

TEST(RestFinishing, ARegionNarrowerThanTheToolOnAWallIsCutNotLeftToAPencil) {
  // A 60° plane wall (x = z / tan 60° from z = 0 to 10) extruded along Y; the stock stands 0.1 mm
  // over it on a patch 0.44 mm wide (|y − 15| < 0.22) from z = 4 to 4.76 (x 2.309 … 2.748). The Ø1
  // ball touches the patch with its axis R·sin 60° = 0.433 mm off it in X: axis positions
  // 0.44 × 0.44 mm (over the sliver limit π·R²/4 = 0.196 mm²), grown by a margin of 0.2 mm to
  // 0.84 mm square — narrower than the tool both ways, on a wall with no concave edge to trace. Its
  // passes must take the patch (each point within the threshold of the ball somewhere), not leave it.
  const double tan60 = std::tan(std::numbers::pi / 3), a = 10 / tan60;
  const ingest::Mesh part = extruded({{-10, 0}, {0, 0}, {a, 10}, {20, 10}}, 30);
  auto design = [&](double x) { return x < 0 ? 0.0 : x < a ? x * tan60 : 10.0; };
  auto in_patch = [&](double x, double y) {
    const double z = design(x);
    return std::abs(y - 15) < 0.22 && z > 4 && z < 4.76;
  };
  RestStock stock;
  stock.cell = 0.02, stock.x0 = -9.99, stock.y0 = 0.01, stock.nx = 1500, stock.ny = 1500;
  stock.z.resize(static_cast<std::size_t>(stock.nx) * static_cast<std::size_t>(stock.ny));
  for (int i = 0; i < stock.ny; ++i)
    for (int j = 0; j < stock.nx; ++j) {
      const double x = stock.x0 + stock.cell * j, y = stock.y0 + stock.cell * i;
      stock.z[static_cast<std::size_t>(i) * static_cast<std::size_t>(stock.nx) + static_cast<std::size_t>(j)] =
          design(x) + (in_patch(x, y) ? 0.1 : 0.0);
    }
  const DropCutter one(part, Cutter::ball(1));
  RestParams rp;
  rp.threshold_mm = kT;
  rp.stock = &stock;
  rp.reference = Cutter::ball(1);
  rp.margin_mm = 0.2;
  const RestRegions r = rest_regions(part, one, rp, -10, 0, 20, 30);
  ASSERT_EQ(r.regions, 1U);
  ASSERT_EQ(r.parts.size(), 1U);
  double wx = 0, wy = 0;  // the outline's extent
  {
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    for (const auto& poly : r.parts.front().boundary.polygons)
      for (const Eigen::Vector2d& q : poly)
        x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
    wx = x1 - x0, wy = y1 - y0;
  }
  EXPECT_LT(wx, 1.0);
  EXPECT_LT(wy, 1.0);
  FinishParams params = rest_params();
  params.tool = Cutter::ball(1);
  const FinishPlan plan = plan_rest(part, one, r, "the stock", params);
  std::vector<Eigen::Vector3d> centres;  // the ball's centre every 0.02 mm along the passes
  for (const Pass& pass : plan.passes)
    for (std::size_t q = 1; q < pass.points.size(); ++q) {
      const Eigen::Vector3d &b = pass.points[q - 1], &e = pass.points[q];
      const int n = std::max(1, static_cast<int>(std::ceil((e - b).norm() / 0.02)));
      for (int k = 0; k <= n; ++k) centres.push_back(b + (e - b) * k / n + Eigen::Vector3d(0, 0, 0.5));
    }
  ASSERT_FALSE(centres.empty());
  for (const Eigen::Vector3d& c : centres) {  // near the patch and never into the wall
    EXPECT_NEAR(c.y(), 15, 0.22 + 0.2 + 0.5) << c.transpose();
    EXPECT_GE(distance_to_mesh(part, c), 0.5 - 1e-4) << c.transpose();
  }
  std::size_t checked = 0;
  for (double z = 4.02; z < 4.75; z += 0.03)
    for (double y = 14.79; y < 15.21; y += 0.03) {
      const Eigen::Vector3d p(z / tan60, y, z);
      double d = HUGE_VAL;
      for (const Eigen::Vector3d& c : centres) d = std::min(d, (p - c).norm() - 0.5);
      EXPECT_LE(d, kT) << "rest left at " << p.transpose();
      ++checked;
    }
  EXPECT_GT(checked, 50U);
}

/// A V-groove along Y over [0, 10], its faces sloping 14° (152° between them), and a stock made by
/// hand on 0.02 mm cells standing 0.05 mm over the crease, falling 0.5 mm per mm to nothing 0.1 mm
/// off it; its rest regions for the Ø1 from that stock at kT.
struct VGroove {
  double slope = std::tan(14 * std::numbers::pi / 180);
  ingest::Mesh part = extruded({{-5, 5 * slope}, {0, 0}, {5, 5 * slope}}, 10);
  RestStock stock = stock_along_x(0.02, -4.995, 0.005, 500,
                                  [this](double x) { return design(x) + std::max(0.0, 0.05 - 0.5 * std::abs(x)); });
  [[nodiscard]] double design(double x) const { return std::abs(x) * slope; }
  [[nodiscard]] RestRegions regions(const DropCutter& one) const {
    RestParams rp;
    rp.threshold_mm = kT;
    rp.stock = &stock;
    rp.reference = Cutter::ball(1);
    return rest_regions(part, one, rp, -5, 0, 5, 10);
  }
};

TEST(RestFinishing, APassIsKeptWhereItRemovesRestBetweenTwoContactsThatReadNone) {
  // A V-groove along Y, its faces sloping 14° (152° between them): the Ø1 ball never touches the
  // design nearer its crease than R / tan 76° = 0.1247 mm, where it stands on both faces with its
  // lowest point R / sin 76° − R = 0.0153 mm over the crease. The stock stands 0.05 mm over the
  // crease, falling 0.5 mm per mm to nothing 0.1 mm off it: every contact of a pass across the
  // groove reads no rest, yet the ball in the groove takes 0.0335 mm off the cells 0.005 mm from
  // the crease (normal to its surface; 1.5 kT = 0.03), leaving 0.0153 (under kT = 0.02). Judged
  // by its contacts alone the pass is left out; judged by what it removes it is kept where it
  // crosses the crease, and only there.
  const VGroove g;
  const ingest::Mesh& part = g.part;
  const DropCutter one(part, Cutter::ball(1));
  const RestRegions r = g.regions(one);
  ASSERT_TRUE(r.from_stock);
  Pass across;  // x from −1 to 1 at y = 5, on the design
  for (int k = 0; k <= 200; ++k) {
    const double x = -1 + 0.01 * k;
    across.points.emplace_back(x, 5, one.drop(x, 5).z);
  }
  EXPECT_NEAR(one.drop(0, 5).z, 0.5 / std::sin(76 * std::numbers::pi / 180) - 0.5, 1e-4);
  // By the contacts alone (the same regions, their stock not followed): nothing kept.
  RestRegions contacts = r;
  contacts.from_stock = false;
  EXPECT_TRUE(detail::trim_to_rest({across}, one, part, contacts).front().empty());
  const std::vector<Pass> kept = detail::trim_to_rest({across}, one, part, r).front();
  ASSERT_EQ(kept.size(), 1U);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const Eigen::Vector3d& q : kept.front().points) lo = std::min(lo, q.x()), hi = std::max(hi, q.x());
  EXPECT_LT(lo, -0.05);
  EXPECT_GT(hi, 0.05);
  // Where the ball removes more than 1.5 kT: the stock over its surface; beyond, the run-on (R / 32).
  EXPECT_GT(lo, -0.1247 - 0.015625 - 1e-3);
  EXPECT_LT(hi, 0.1247 + 0.015625 + 1e-3);
  // A second pass along the first is judged on what the first left: nothing more to take.
  EXPECT_TRUE(detail::trim_to_rest({across, across}, one, part, r)[1].empty());
}

// The design points a rest program is judged by (detail::RestPoints), on the V-groove above: the
// stock stands over the design by 0.05 − 0.5·|x| near the crease, over kT for |x| < 0.06 only
// (along the normal, cos 14° of it: |x| < 0.0588). The Ø1 in the groove comes 0.0153 mm from the
// crease: within kT of those points; 2 mm off the crease it is nowhere near them. After a pass
// along the groove over y in [2, 6], the points there are cleared, and those beyond are not.
TEST(RestPoints, ThePointsOverTheThresholdAndWhichTheToolHasComeWithinItOf) {
  const VGroove g;
  const ingest::Mesh& part = g.part;
  const DropCutter one(part, Cutter::ball(1));
  const RestRegions r = g.regions(one);
  detail::RestPoints points(part, r, Cutter::ball(1), 0.01, kT);
  ASSERT_GT(points.size(), 0U);
  for (const Eigen::Vector3d& p : points.points()) {
    EXPECT_LT(std::abs(p.x()), 0.0588 + 0.02 + 1e-9);  // a cell's reading of the stock beside it
    EXPECT_NEAR(p.z(), g.design(p.x()), 1e-3);         // on the design
  }
  // Every 0.01 mm along the crease (y in [1, 9]) some point lies within 0.02 of it.
  for (int k = 0; k <= 800; ++k) {
    const double y = 1 + 0.01 * k;
    EXPECT_TRUE(std::any_of(points.points().begin(), points.points().end(), [&](const Eigen::Vector3d& p) {
      return std::hypot(p.x(), p.y() - y) <= 0.02;
    })) << y;
  }
  const double groove = one.drop(0, 5).z;
  EXPECT_TRUE(points.needed({0, 5, groove}));
  EXPECT_FALSE(points.needed({2, 5, one.drop(2, 5).z}));
  EXPECT_FALSE(points.needed({0, 5, groove + 0.05}));  // 0.0653 over the crease: farther than kT
  points.clear_along({{0, 2, groove}, {0, 6, groove}});
  EXPECT_FALSE(points.needed({0, 4, groove}));
  EXPECT_FALSE(points.needed({0, 5.9, groove}));
  EXPECT_TRUE(points.needed({0, 7.5, groove}));
  EXPECT_TRUE(points.needed({0, 1, groove}));
}

// Passes aimed at what the passes left (detail::aim_at_rest), on the V-groove above. The Ø1 in
// the groove comes 0.0153 mm from the crease and nearer every point of the band beside it: it
// reaches all the points. Every placement of the aimed passes is the drop-cutter's (no gouge), they stay within R·sin 14° (0.121 mm: a ball on one face touches it
// that far beyond its axis) of the band of points (|x| < 0.0788), and every point they count as
// covered lies within kT of a placement along them (checked again every 0.005 mm with the exact
// distance); none is left but one alone at an end of the stretch to cover. After a pass
// along the groove over y in [2, 6] no aimed pass runs there, and they are one pass on either side.
TEST(RestFinishing, PassesAreAimedAtTheRestThePassesLeftAndOnlyThere) {
  const VGroove g;
  const ingest::Mesh& part = g.part;
  const DropCutter one(part, Cutter::ball(1));
  const RestRegions r = g.regions(one);
  const double groove = one.drop(0, 5).z;
  auto aimed = [&](bool middle_cut) {
    detail::RestPoints points(part, r, Cutter::ball(1), 0.01, kT);
    if (middle_cut) points.clear_along({{0, 2, groove}, {0, 6, groove}});
    const std::vector<Pass> passes = detail::aim_at_rest(
        part, one, points, 0.01, [](const Eigen::Vector3d&) { return true; }, -std::numeric_limits<double>::infinity());
    // Left: only a point alone in reach of its nearest placement (fewer than
    // tol::rest_aim_min_points), at most one at each end of a stretch to cover.
    std::vector<Eigen::Vector3d> covered;
    for (std::size_t k = 0; k < points.size(); ++k)
      if (points.is_cleared(k)) covered.push_back(points.points()[k]);
    EXPECT_LE(points.size() - covered.size(), middle_cut ? 4U : 2U);
    return std::pair{passes, covered};
  };
  for (const bool middle_cut : {false, true}) {
    const auto [passes, targets] = aimed(middle_cut);
    ASSERT_FALSE(passes.empty());
    std::vector<Eigen::Vector3d> along;  // placements every 0.005 mm, the middle pass's too
    for (int k = 0; middle_cut && k <= 800; ++k) along.emplace_back(0, 2 + 0.005 * k, groove);
    for (const Pass& pass : passes)
      for (std::size_t k = 0; k < pass.points.size(); ++k) {
        const Eigen::Vector3d& q = pass.points[k];
        EXPECT_NEAR(q.z(), one.drop(q.x(), q.y()).z, 1e-9);
        EXPECT_LT(std::abs(q.x()), 0.0788 + 0.1210 + 1e-3);
        if (middle_cut) EXPECT_FALSE(q.y() > 2.2 && q.y() < 5.8) << q.transpose();
        if (k == 0) continue;
        const Eigen::Vector3d& a = pass.points[k - 1];
        const int n = std::max(1, static_cast<int>(std::ceil((q - a).norm() / 0.005)));
        for (int t = 0; t <= n; ++t) along.push_back(a + (q - a) * (static_cast<double>(t) / n));
      }
    std::sort(along.begin(), along.end(), [](const auto& a, const auto& b) { return a.y() < b.y(); });
    for (const Eigen::Vector3d& p : targets) {
      double gap = HUGE_VAL;  // over the placements within R + kT along y
      auto c = std::lower_bound(along.begin(), along.end(), p.y() - 0.52,
                                [](const Eigen::Vector3d& a, double y) { return a.y() < y; });
      for (; c != along.end() && c->y() <= p.y() + 0.52; ++c)
        gap = std::min(gap, Cutter::ball(1).distance_to_solid(c->x(), c->y(), c->z(), p.x(), p.y(), p.z()));
      EXPECT_LE(gap, kT) << p.transpose();
    }
    EXPECT_LE(passes.size(), middle_cut ? 2U : 1U);
  }
}

// Where every placement that reaches a point is kept (tol::rest_aim_min_points_measured: a rest
// measured by the programs), the aimed passes leave no point of the V-groove's band that the Ø1
// reaches — the lone points at the ends of the stretch the default's four-point rule leaves
// (above) included — and still stay on the drop-cutter's placements.
TEST(RestFinishing, AimedAtEveryPointWhereOnePointIsEnough) {
  const VGroove g;
  const ingest::Mesh& part = g.part;
  const DropCutter one(part, Cutter::ball(1));
  const RestRegions r = g.regions(one);
  const double none = -std::numeric_limits<double>::infinity();
  auto left_after = [&](std::size_t min_points, std::vector<Pass>* out) {
    detail::RestPoints points(part, r, Cutter::ball(1), 0.01, kT);
    *out = detail::aim_at_rest(
        part, one, points, 0.01, [](const Eigen::Vector3d&) { return true; }, none, min_points);
    return points.uncleared().size();
  };
  std::vector<Pass> four, single;
  EXPECT_GT(left_after(tol::rest_aim_min_points, &four), 0U);  // the lone points at the ends
  EXPECT_EQ(left_after(tol::rest_aim_min_points_measured, &single), 0U);
  ASSERT_FALSE(single.empty());
  for (const Pass& pass : single)
    for (const Eigen::Vector3d& q : pass.points) EXPECT_NEAR(q.z(), one.drop(q.x(), q.y()).z, 1e-9);
}

// The aimed passes' search skips the points below the lowest tip allowed less the threshold (the
// tool's solid lies on and above its tip): with a fence that keeps tips at or above a height, the
// skip changes nothing, at four heights; with the lowest tip above every point by more than
// the threshold, nothing is aimed even where every placement is allowed.
TEST(RestFinishing, AimedPassesSkipOnlyThePointsNoAllowedTipReaches) {
  const VGroove g;
  const ingest::Mesh& part = g.part;
  const DropCutter one(part, Cutter::ball(1));
  const RestRegions r = g.regions(one);
  const double groove = one.drop(0, 5).z;
  auto aimed = [&](double floor, double lowest) {
    detail::RestPoints points(part, r, Cutter::ball(1), 0.01, kT);
    return detail::aim_at_rest(
        part, one, points, 0.01, [floor](const Eigen::Vector3d& q) { return q.z() >= floor; }, lowest);
  };
  const double none = -std::numeric_limits<double>::infinity();
  std::size_t kept = 0;
  for (const double floor : {none, groove, groove + 0.004, groove + 0.02}) {
    const std::vector<Pass> all = aimed(floor, none), skipped = aimed(floor, floor);
    ASSERT_EQ(all.size(), skipped.size()) << floor;
    for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(all[k].points, skipped[k].points) << floor;
    kept += all.size();
  }
  EXPECT_GT(kept, 0U);
  double top = -HUGE_VAL;
  {
    const detail::RestPoints points(part, r, Cutter::ball(1), 0.01, kT);
    for (std::size_t k = 0; k < points.size(); ++k) top = std::max(top, points.points()[k].z());
  }
  EXPECT_TRUE(aimed(none, top + kT + 1e-6).empty());
  EXPECT_FALSE(aimed(none, top + kT - 1e-3).empty());
}

TEST(RestRegions, BadParametersAndASmallerReferenceAreRefused) {
  const ingest::Mesh part = l_corner();
  const DropCutter two(part, Cutter::ball(2));
  RestParams rp;
  rp.reference = Cutter::ball(1);
  EXPECT_THROW((void)rest_regions(part, two, rp), Error);
  rp.reference = Cutter::ball(6);
  rp.threshold_mm = 0;
  EXPECT_THROW((void)rest_regions(part, two, rp), Error);
  rp.threshold_mm = 0.02;
  rp.cell_mm = 0.001;
  EXPECT_THROW((void)rest_regions(part, two, rp), Error);
  // Nothing to take: the same tool as the reference leaves no rest, and plan_rest says so.
  rp.cell_mm = 0;
  rp.reference = Cutter::ball(2);
  const RestRegions none = rest_regions(part, two, rp, -2, 10, 6, 16);  // wall, fillet and floor
  EXPECT_TRUE(none.empty());
  EXPECT_THROW((void)plan_rest(part, two, none, rp.reference.describe(), rest_params()), Error);
}

// A V-groove along Y with 45° flanks (z = |x|): the Ø2 ball touches both flanks with its centre at
// x = 0, R / cos 45° = √2 high, so its tip runs along x = 0 at z = √2 − 1 = 0.41421.
TEST(Pencil, FollowsTheVGroovesBitangentLine) {
  ingest::Mesh m;
  m.V.resize(6, 3);
  m.V << -8, 0, 8, 0, 0, 0, 8, 0, 8, -8, 20, 8, 0, 20, 0, 8, 20, 8;
  m.F.resize(4, 3);
  m.F << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
  const DropCutter two(m, Cutter::ball(2));
  FinishParams p = rest_params();
  p.safe_z_mm = 30;
  p.boundary.polygons = {{{-6, 2}, {6, 2}, {6, 18}, {-6, 18}}};  // away from the open ends
  const FinishPlan plan = plan_pencil(m, two, p);
  ASSERT_EQ(plan.passes.size(), 1U);
  const Pass& pass = plan.passes.front();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const Eigen::Vector3d& q : pass.points) {
    EXPECT_NEAR(q.x(), 0, p.chord_tolerance_mm) << q.transpose();
    EXPECT_NEAR(q.z(), std::sqrt(2.0) - 1, p.chord_tolerance_mm) << q.transpose();
    lo = std::min(lo, q.y()), hi = std::max(hi, q.y());
  }
  EXPECT_LT(lo, 2.2);
  EXPECT_GT(hi, 17.8);
  // Multi-pencil: two passes each side, 0.5 mm apart in XY, outermost first, the groove last; on a
  // flank the ball touches one plane only, its tip at z = |x| + √2 − 1 (hand-computed).
  FinishParams q = p;
  q.stepover_mm = 0.5;
  const FinishPlan multi = plan_pencil(m, two, q, 2);
  ASSERT_EQ(multi.passes.size(), 5U);
  const double want_x[] = {1.0, 0.5, -1.0, -0.5, 0.0};
  for (std::size_t k = 0; k < 5; ++k) {
    SCOPED_TRACE(k);
    ASSERT_GE(multi.passes[k].points.size(), 2U);
    double y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
    for (const Eigen::Vector3d& c : multi.passes[k].points) {
      // the pass's direction along Y may alternate (the links), its XY offset may not
      EXPECT_NEAR(std::abs(c.x()), std::abs(want_x[k]), 1e-9) << c.transpose();
      EXPECT_NEAR(c.z(), std::abs(want_x[k]) + std::sqrt(2.0) - 1, p.chord_tolerance_mm) << c.transpose();
      y_lo = std::min(y_lo, c.y()), y_hi = std::max(y_hi, c.y());
    }
    EXPECT_LT(y_lo, 2.2);
    EXPECT_GT(y_hi, 17.8);
  }
  // The two sides are on opposite flanks.
  EXPECT_LT(multi.passes[0].points.front().x() * multi.passes[2].points.front().x(), 0);
  EXPECT_THROW((void)plan_pencil(m, two, q, 51), Error);
  // A plane has no concave edge: nothing to trace, said so.
  ingest::Mesh flat;
  flat.V.resize(4, 3);
  flat.V << 0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0;
  flat.F.resize(2, 3);
  flat.F << 0, 1, 2, 0, 2, 3;
  EXPECT_THROW((void)plan_pencil(flat, DropCutter(flat, Cutter::ball(2)), rest_params()), Error);
}

// A staircase of 1.5 mm risers and 0.2 mm treads (a steep concave slope at 82°) seen by a Ø1 ball:
// the drops jump from step to step, so bitangent positions are found on every step, 0.2 mm apart
// in XY and 1.5 mm in Z. Each pencil pass follows one step along Y; chaining by XY alone joined the
// steps into passes that climbed from one to the next (test part s1's steep slopes, 2 mm up and
// down every tenth of a millimetre).
TEST(Pencil, PassesOnASteepStaircaseStayOnTheirStep) {
  constexpr double kW = 0.2, kH = 1.5;
  constexpr int kSteps = 6;
  std::vector<Eigen::Vector2d> prof{{-5, 0}};
  for (int k = 0; k < kSteps; ++k) {
    prof.emplace_back(k * kW, k * kH);
    prof.emplace_back(k * kW, (k + 1) * kH);
  }
  prof.emplace_back(kSteps * kW + 5, kSteps * kH);
  const ingest::Mesh m = extruded(prof, 20);
  const DropCutter one(m, Cutter::ball(1));
  FinishParams p = rest_params();
  p.tool = Cutter::ball(1);
  const FinishPlan plan = plan_pencil(m, one, p);
  // One pass a crease, each straight along Y at its bitangent position (hand-computed): the floor's
  // foot at x = −R, z = 0; above it the ball touching riser k + 1 and nose k at x = k·w − 0.5,
  // tip z = k·h − 0.1 (its centre 0.5 from the riser, 0.3 from the nose in X and 0.4 in Z: 0.5 = R).
  ASSERT_EQ(plan.passes.size(), static_cast<std::size_t>(kSteps));
  std::vector<const Pass*> by_z;
  for (const Pass& pass : plan.passes) by_z.push_back(&pass);
  std::sort(by_z.begin(), by_z.end(), [](const Pass* a, const Pass* b) { return a->points[0].z() < b->points[0].z(); });
  for (int k = 0; k < kSteps; ++k) {
    SCOPED_TRACE(k);
    double y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
    for (const Eigen::Vector3d& q : by_z[static_cast<std::size_t>(k)]->points) {
      EXPECT_NEAR(q.x(), k * kW - 0.5, 1e-4) << q.transpose();
      EXPECT_NEAR(q.z(), k == 0 ? 0.0 : k * kH - 0.1, p.chord_tolerance_mm) << q.transpose();
      y_lo = std::min(y_lo, q.y()), y_hi = std::max(y_hi, q.y());
    }
    EXPECT_GT(y_hi - y_lo, 19.0);  // along the whole step
  }
}

}  // namespace
}  // namespace millnet::finish
