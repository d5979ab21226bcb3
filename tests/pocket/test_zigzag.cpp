// Zigzag paths: gouge-free by the independent G-code replay, coverage against the analytic cusp
// bound, one connected chain per region, retractions = regions − 1.
#include "testing/program_text.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/planner_zigzag.hpp"
#include "testing/gcode_replay.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace millnet::pocket;

namespace {

Loop rect(double x0, double y0, double x1, double y1, bool ccw) {
  Loop l{{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  if (!ccw) std::reverse(l.begin(), l.end());
  return l;
}
Loop circle_cw(double cx, double cy, double r) { return {{cx - r, cy, -1}, {cx + r, cy, -1}}; }

CutParams tool10() {
  CutParams c;
  c.tool.diameter = 10;
  c.stepover = 5;
  c.depth = 5;
  c.step_down = 5;
  return c;
}

millnet::testing::ReplayLoop replay_loop(const Loop& l) {
  millnet::testing::ReplayLoop out;
  for (const Vertex& v : l) out.push_back({v.x, v.y, v.bulge});
  return out;
}

/// Writes the plan as G-code with pocketcore's writer and re-reads it with the independent replay.
millnet::testing::ReplayResult replay(const Region& region, const PlanResult& plan, const CutParams& cut) {
  LevelPlan L;
  L.z = -cut.depth;
  L.top_z = 0;
  L.region = region;
  L.path = plan.path;
  L.predrill = plan.predrill;
  GcodeParams gp;
  gp.cut = cut;
  const std::string text = millnet::testing::linuxcnc_text(build_program({L}, gp));
  auto r = millnet::testing::replay_gcode(text, cut.safe_z);
  millnet::testing::ReplayPocket pocket{replay_loop(region.boundary), {}};
  for (const Loop& i : region.islands) pocket.islands.push_back(replay_loop(i));
  millnet::testing::check_gouge(r, pocket, cut.tool.diameter / 2, 0.01, 0.05);
  return r;
}

/// Fine raster: cells whose centre is within r of segments, or inside polygons (test-only oracle).
struct Raster {
  double x0, y0, h;
  int nx, ny;
  std::vector<char> cell;
  Raster(double ax, double ay, double bx, double by, double hh)
      : x0(ax),
        y0(ay),
        h(hh),
        nx(static_cast<int>(std::ceil((bx - ax) / hh))),
        ny(static_cast<int>(std::ceil((by - ay) / hh))),
        cell(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0) {}
  Vec2 center(int i, int j) const { return {x0 + (i + 0.5) * h, y0 + (j + 0.5) * h}; }
  char& at(int i, int j) {
    return cell[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
  }
  void capsule(const Vec2& a, const Vec2& b, double r) {  // O(bbox cells)
    const int i0 = std::max(0, static_cast<int>(std::floor((std::min(a.x(), b.x()) - r - x0) / h)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::ceil((std::max(a.x(), b.x()) + r - x0) / h)));
    const int j0 = std::max(0, static_cast<int>(std::floor((std::min(a.y(), b.y()) - r - y0) / h)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::ceil((std::max(a.y(), b.y()) + r - y0) / h)));
    const Vec2 d = b - a;
    const double dd = d.squaredNorm();
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 p = center(i, j);
        const double t = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
        if ((a + t * d - p).squaredNorm() <= r * r) at(i, j) = 1;
      }
  }
  void fill(const std::vector<PolyArea>& areas) {  // even-odd crossing per row, O(rows · V)
    for (int j = 0; j < ny; ++j) {
      const double y = center(0, j).y();
      std::vector<double> xs;
      auto ring = [&](const std::vector<Vec2>& r) {
        for (std::size_t k = 0; k < r.size(); ++k) {
          const Vec2& a = r[k];
          const Vec2& b = r[(k + 1) % r.size()];
          if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
        }
      };
      for (const auto& a : areas) {
        ring(a.outer);
        for (const auto& hh : a.holes) ring(hh);
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
        for (int i = 0; i < nx; ++i) {
          const double x = center(i, j).x();
          if (x >= xs[k] && x <= xs[k + 1]) at(i, j) = 1;
        }
    }
  }
};

/// Uncut area (mm²) of the region the tool can sweep at all: (reach ⊕ disk R) minus the swept
/// disks of every cutting chain.
double uncut_area(const Region& region, const PlanResult& plan, double R, double h) {
  const auto reach = offset_inward(region, R);
  double lo_x = 1e18, lo_y = 1e18, hi_x = -1e18, hi_y = -1e18;
  for (const Vertex& v : region.boundary) {
    lo_x = std::min(lo_x, v.x);
    lo_y = std::min(lo_y, v.y);
    hi_x = std::max(hi_x, v.x);
    hi_y = std::max(hi_y, v.y);
  }
  Raster target(lo_x - 1, lo_y - 1, hi_x + 1, hi_y + 1, h), cut(lo_x - 1, lo_y - 1, hi_x + 1, hi_y + 1, h);
  target.fill(reach);
  auto rings = [&](auto&& f) {
    for (const auto& a : reach) {
      f(a.outer);
      for (const auto& hh : a.holes) f(hh);
    }
  };
  rings([&](const std::vector<Vec2>& r) {
    for (std::size_t k = 0; k < r.size(); ++k) target.capsule(r[k], r[(k + 1) % r.size()], R);
  });
  for (const Chain& c : plan.path.chains)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) cut.capsule(c.pts[k].p(), c.pts[k + 1].p(), R);
  std::size_t n = 0;
  for (std::size_t k = 0; k < target.cell.size(); ++k)
    if (target.cell[k] && !cut.cell[k]) ++n;
  return static_cast<double>(n) * h * h;
}

/// Uncut cusp between two pass ends a distance s apart on a wall perpendicular to the passes,
/// tool radius R (s ≤ 2R): the strip s × R minus the two disk pieces,
///   c(s, R) = R·s − (s/2)·sqrt(R² − s²/4) − R²·asin(s / 2R).
double cusp(double s, double R) {
  return R * s - 0.5 * s * std::sqrt(R * R - s * s / 4) - R * R * std::asin(s / (2 * R));
}

}  // namespace

TEST(Zigzag, CuspFormulaHandValues) {
  EXPECT_NEAR(cusp(5, 5), 25 - 2.5 * std::sqrt(18.75) - 25 * std::numbers::pi / 6, 1e-12);
  EXPECT_NEAR(cusp(5, 5), 1.0847, 1e-4);
  EXPECT_NEAR(cusp(1e-3, 5), 0.0, 1e-9);  // touching passes leave nothing
}

TEST(Zigzag, RectangleCoverageMatchesCuspBound) {
  // 100 × 60, R = 5: reach [5, 95] × [5, 55]. Passes span the full width and are joined on
  // alternate sides along the wall, so each of the n − 1 gaps leaves exactly one cusp, on the side
  // where it is not joined. Bound tested: uncut ≤ (n − 1)·c(s', R) + 2·scan_clear·90 (+ raster
  // slack), s' the actual spacing ≤ stepover; and ≥ 90 % of it (the joins must run along the wall).
  Region r{rect(0, 0, 100, 60, true), {}};
  const CutParams cut = tool10();
  ZigzagParams zp;
  const PlanResult p = plan_zigzag(r, cut, zp);
  ASSERT_EQ(p.status, PlanStatus::Ok);
  EXPECT_EQ(p.path.chains.size(), 1u);
  const double n = static_cast<double>(std::get<ZigzagStats>(p.stats).passes);
  EXPECT_EQ(n, 11.0);  // ceil(49.996 / 5) + 1
  const double s = (50 - 2 * tol::scan_clear_mm) / (n - 1);
  const double predicted = (n - 1) * cusp(s, 5) + 2 * tol::scan_clear_mm * 90;
  const double uncut = uncut_area(r, p, 5, 0.05);
  std::printf("rectangle: uncut %.3f mm², predicted %.3f mm²\n", uncut, predicted);
  EXPECT_LE(uncut, predicted * 1.05 + 0.3);
  EXPECT_GE(uncut, predicted * 0.9 - 0.3);
  // Cut length: 11 passes of 90 + 10 joins of s.
  EXPECT_NEAR(p.path.cut_length(), 11 * 90 + 10 * s, 1e-3);
  const auto rep = replay(r, p, cut);
  EXPECT_EQ(rep.violations, 0) << rep.first_violation;
}

TEST(Zigzag, ContourLeavesNothingOnFourIslands) {
  Region r{rect(0, 0, 120, 100, true),
           {circle_cw(35, 30, 15), circle_cw(85, 30, 15), circle_cw(35, 70, 15), circle_cw(85, 70, 15)}};
  const CutParams cut = tool10();
  for (auto kind : {PartitionKind::T, PartitionKind::I}) {
    ZigzagParams zp;
    zp.partition = kind;
    const PlanResult q = plan_zigzag(r, cut, zp);
    ASSERT_EQ(q.status, PlanStatus::Ok);
    // With the contour pass along every offset wall (machine_pocket's, the same for every planner),
    // only raster noise may stay uncut (≤ 50 cells).
    PlanResult p = q;
    for (auto& c : contour_chains(r, cut, q.path)) p.path.chains.push_back(std::move(c));
    const double uncut = uncut_area(r, p, 5, 0.1);
    std::printf("four islands %s + contour: uncut %.3f mm²\n", p.planner.c_str(), uncut);
    EXPECT_LE(uncut, 0.5);
    const auto rep = replay(r, p, cut);
    EXPECT_EQ(rep.violations, 0) << rep.first_violation;
    EXPECT_GT(rep.samples, 1000);
    // Without the contour: more uncut (the cusps at pass ends on slanted walls), bounded by the wall
    // band on the unjoined side: each gap between two passes is joined along the wall on one side,
    // so at most half of the band of width R along the reach walls stays: R · perimeter / 2.
    const double uncut2 = uncut_area(r, q, 5, 0.1);
    double perim = 0;
    for (const auto& a : offset_inward(r, 5)) {
      auto ring = [&](const std::vector<Vec2>& v) {
        for (std::size_t k = 0; k < v.size(); ++k) perim += (v[(k + 1) % v.size()] - v[k]).norm();
      };
      ring(a.outer);
      for (const auto& h : a.holes) ring(h);
    }
    std::printf("  without contour: uncut %.3f mm² (bound R·P/2 = %.1f)\n", uncut2, 5 * perim / 2);
    EXPECT_GT(uncut2, uncut);
    EXPECT_LE(uncut2, 5 * perim / 2);
  }
}

TEST(Zigzag, OneChainPerRegionAndRetractions) {
  // Seed Fig. 5(b) pocket: T gives 3 regions, I gives 2; each region is one connected chain that
  // stays inside the reachable area. Unlinked (the seed's plan): retractions = regions − 1, one
  // predrill per region. Linked (issue 11): every region here meets the area the ones before it
  // cut, so one chain, no retraction, one predrill.
  Region r{rect(0, 0, 120, 100, true), {rect(20, 15, 40, 35, false), rect(70, 60, 90, 80, false)}};
  const CutParams cut = tool10();
  const Clearance clear(r, cut.clearance());
  for (auto [kind, regions] : {std::pair{PartitionKind::T, 3}, std::pair{PartitionKind::I, 2}}) {
    for (const bool link : {false, true}) {
      SCOPED_TRACE(link ? "linked" : "unlinked");
      ZigzagParams zp;
      zp.partition = kind;
      zp.link_regions = link;
      const PlanResult p = plan_zigzag(r, cut, zp);
      ASSERT_EQ(p.status, PlanStatus::Ok);
      const auto& st = std::get<ZigzagStats>(p.stats);
      EXPECT_EQ(st.regions, regions);
      const std::size_t chains = link ? 1 : static_cast<std::size_t>(regions);
      EXPECT_EQ(st.region_links, static_cast<std::size_t>(regions) - chains);
      EXPECT_EQ(p.path.chains.size(), chains);
      EXPECT_EQ(p.path.retractions(), chains - 1);
      EXPECT_EQ(p.predrill.size(), chains);
      const auto rep = replay(r, p, cut);
      EXPECT_EQ(rep.violations, 0) << rep.first_violation;
      EXPECT_LT(uncut_area(r, p, 5, 0.1), 2 * static_cast<double>(st.passes) * cusp(5, 5) + 0.5);
    }
  }
}

TEST(Zigzag, GougeFreeAtOddAnglesWithArcs) {
  // Round outline with a slot island and a triangle: arcs everywhere, directions not on the grid.
  Region r{{{75, 0, 1}, {-75, 0, 1}},
           {{{30, 8, 0}, {50, 8, 0}, {50, -8, 0}, {30, -8, 0}},
            {{-50, 8, 0}, {-30, 8, -0.4}, {-30, -8, 0}, {-50, -8, -0.4}},
            {{35, 45, 0}, {45, 30, 0}, {25, 25, 0}},
            circle_cw(0, 0, 12)}};
  const CutParams cut = tool10();
  for (double ang : {0.0, 17.0, 62.5, 90.0, 151.0}) {
    ZigzagParams zp;
    zp.angle_deg = ang;
    zp.partition = PartitionKind::I;
    const PlanResult p = plan_zigzag(r, cut, zp);
    ASSERT_EQ(p.status, PlanStatus::Ok);
    const ZigzagStats& st = std::get<ZigzagStats>(p.stats);
    EXPECT_EQ(st.nonmonotone_faces, 0) << ang;
    EXPECT_EQ(st.faces, static_cast<std::size_t>(st.formula_regions)) << ang;
    const auto rep = replay(r, p, cut);
    EXPECT_EQ(rep.violations, 0) << "angle " << ang << ": " << rep.first_violation;
  }
}

TEST(Zigzag, ToolTooBigIsAStatus) {
  Region r{rect(0, 0, 8, 8, true), {}};
  const PlanResult p = plan_zigzag(r, tool10(), ZigzagParams{});
  EXPECT_EQ(p.status, PlanStatus::NoToolPoints);
  EXPECT_TRUE(p.path.chains.empty());
  EXPECT_FALSE(p.message.empty());
}

TEST(Zigzag, BadStepoverThrows) {
  Region r{rect(0, 0, 80, 80, true), {}};
  CutParams c = tool10();
  c.stepover = 12;
  EXPECT_THROW((void)plan_zigzag(r, c, ZigzagParams{}), millnet::Error);
  c.stepover = 0;
  EXPECT_THROW((void)plan_zigzag(r, c, ZigzagParams{}), millnet::Error);
}
