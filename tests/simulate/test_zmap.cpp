// Z-map virtual machining: exact grooves (line, arc), scallops of ball rasters on a plane and a
// tilted plane, flat end mill, gouge reporting, depth of cut in a rough → finish chain, cutting
// rapids, dense-sampling oracle for every cutter, thread-count independence, memory refusal.
#include "millnet/simulate/zmap.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

using namespace millnet;
using namespace millnet::simulate;
using gcode::Motion;
using gcode::Move;
using gcode::Program;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Move mv(Motion m, double x, double y, double z, double cx = 0, double cy = 0) {
  Move v;
  v.motion = m;
  v.to = {x, y, z};
  v.center = {cx, cy};
  v.feed = m == Motion::Rapid ? 0 : 1000;
  return v;
}

void add(Program& p, Move m) { p.items.emplace_back(m); }

double ball_f(double R, double r) { return R - std::sqrt(R * R - r * r); }

// A raster of passes along X at y = y_first + k·step (k < n), tip height z(y), from x0 to x1.
Program raster(double x0, double x1, double y_first, double step, int n, double (*zf)(double)) {
  Program p;
  for (int k = 0; k < n; ++k) {
    const double y = y_first + step * k;
    add(p, mv(Motion::Rapid, x0, y, 5));
    add(p, mv(Motion::Line, x0, y, zf(y)));
    add(p, mv(Motion::Line, x1, y, zf(y)));
    add(p, mv(Motion::Rapid, x1, y, 5));
  }
  return p;
}

// Design NaN outside [xa, xb] × [ya, yb].
std::vector<double> design_window(const GridSpec& g, double xa, double xb, double ya, double yb, double (*zf)(double)) {
  std::vector<double> d(g.cells(), kNaN);
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double x = g.x(ix), y = g.y(iy);
      if (x >= xa && x <= xb && y >= ya && y <= yb) d[iy * g.nx + ix] = zf(y);
    }
  return d;
}

double zero(double) { return 0; }

/// The concave corner of the rest-material tests: a floor at 0 for x < 3 and a vertical wall up
/// to a top at 5 for x ≥ 3, judged over [0.5, 4] × [1, 3] on `g` (NaN elsewhere).
std::vector<double> corner_design(const GridSpec& g) {
  std::vector<double> design(g.cells(), kNaN);
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double x = g.x(ix), y = g.y(iy);
      if (x >= 0.5 && x <= 4 && y >= 1 && y <= 3 + 1e-9) design[iy * g.nx + ix] = x < 3 - 1e-9 ? 0 : 5;
    }
  return design;
}

/// Passes along Y every 0.1 mm over the corner for a ball of radius R: on the floor up to
/// x = 2.99 − R (the ball next to the wall; at 3 − R it would reach the wall's cells at its
/// equator), on the top from x = 3.
Program corner_passes_along_y(double R) {
  Program p;
  auto pass = [&](double x, double z) {
    add(p, mv(Motion::Rapid, x, -2, 8));
    add(p, mv(Motion::Line, x, -2, z));
    add(p, mv(Motion::Line, x, 7, z));
    add(p, mv(Motion::Rapid, x, 7, 8));
  };
  for (int k = 0; 0.1 * k < 2.99 - R; ++k) pass(0.1 * k, 0);
  pass(2.99 - R, 0);
  for (int k = 0; k <= 15; ++k) pass(3 + 0.1 * k, 5);
  return p;
}

}  // namespace

TEST(ZMap, BallLineLeavesExactCircularGroove) {
  const GridSpec g{0, 0, 0.05, 200, 80};
  ZMap zm = ZMap::flat(g, 0);
  Program p;
  add(p, mv(Motion::Rapid, -2, 2.025, 5));  // on a row of cell centres
  add(p, mv(Motion::Line, -2, 2.025, -0.3));
  add(p, mv(Motion::Line, 12, 2.025, -0.3));
  add(p, mv(Motion::Rapid, 12, 2.025, 5));
  const auto res = machine(zm, p, tooling::Cutter::ball(2));
  EXPECT_TRUE(res.cutting_rapids.empty());
  EXPECT_EQ(res.feed_moves, 2u);
  EXPECT_EQ(res.rapid_moves, 2u);
  EXPECT_NEAR(res.max_cut_mm[kLineKind], 0.3, 1e-12);
  EXPECT_NEAR(res.feed_length_mm, 19.3, 1e-12);
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double dy = std::abs(g.y(iy) - 2.025);
      const double expect = dy < 1 ? std::min(0.0, -0.3 + ball_f(1, dy)) : 0.0;
      ASSERT_NEAR(zm.at(ix, iy), expect, 1e-12) << ix << "," << iy;
      MoveRef ref;
      if (expect < 0) {
        ASSERT_TRUE(zm.origin(iy * g.nx + ix, ref));
        EXPECT_EQ(ref.item, 2u);
        EXPECT_EQ(ref.pass, 0u);
      } else {
        EXPECT_FALSE(zm.origin(iy * g.nx + ix, ref));
      }
    }
}

TEST(ZMap, BallRasterOnPlaneLeavesTheoreticalScallop) {
  const double p = 0.2, R = 1;
  const GridSpec g{-0.005, -0.005, 0.01, 400, 400};  // cell centres at multiples of 0.01: on the cusps
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-2, 6, -1.0, p, 31, zero), tooling::Cutter::ball(2 * R));
  const auto m = surface_metrics(zm, design_window(g, 1, 3, 1, 3, zero));
  const double h = R - std::sqrt(R * R - p * p / 4);
  EXPECT_NEAR(m.scallop_max_mm, h, 0.02 * h);
  EXPECT_FALSE(m.gouged);
  EXPECT_GE(m.min_e_mm, -1e-12);
  EXPECT_NEAR(m.min_e_mm, 0, 1e-12);
  // Ra of the scallop profile (its analytic value is ≈ h/4 for a parabola-like arc profile).
  EXPECT_GT(m.ra_median_um, 0.5);
  EXPECT_LT(m.ra_median_um, 1000 * h / 2);
  EXPECT_EQ(m.ra_cells, m.surface_cells);
  double share = 0;
  for (double s : m.ra_share) share += s;
  EXPECT_NEAR(share, 1, 1e-12);
  EXPECT_GE(m.ra_p90_um, m.ra_median_um);
}

namespace {
constexpr double kAlpha = 20 * std::numbers::pi / 180;
double tilted(double y) { return y * std::tan(kAlpha); }
double tilted_tip(double y) { return y * std::tan(kAlpha) + 1.0 / std::cos(kAlpha) - 1.0; }  // ball R = 1
}  // namespace

TEST(ZMap, BallRasterOnTiltedPlaneUsesTheThreeDStepover) {
  const double py = 0.2, R = 1;
  const double s = py / std::cos(kAlpha);              // 3D stepover along the plane
  const double hn = R - std::sqrt(R * R - s * s / 4);  // scallop normal to the plane
  // Put cell centres on the cusps: y = midpoint + √(R² − s²/4)·sin α (+ k·py, py = 20 cells).
  const double cusp = 0.1 + std::sqrt(R * R - s * s / 4) * std::sin(kAlpha);
  const double cell = 0.01;
  const double y0 = cusp - 0.5 * cell - 100 * cell;
  const GridSpec g{-0.005, y0, cell, 400, 400};
  ZMap zm = ZMap::flat(g, 10);
  machine(zm, raster(-2, 6, 0.2 * std::round((y0 - 1.5) / 0.2), py, 40, tilted_tip), tooling::Cutter::ball(2 * R));
  const double ya = y0 + 1, yb = y0 + 3;
  const auto m = surface_metrics(zm, design_window(g, 1, 3, ya, yb, tilted));
  EXPECT_NEAR(m.scallop_max_mm, hn, 0.02 * hn);  // measured along the plane's normal
  EXPECT_NEAR(m.min_e_mm, 0, 2e-5);              // the contact lines fall between cell centres
  EXPECT_GE(m.min_e_mm, -1e-12);
  EXPECT_FALSE(m.gouged);
}

TEST(ZMap, WithTheCutterScallopsBetweenPassesAreToldFromUncutBands) {
  // Passes along X on a plane at y = 0 … 1.0 every 0.2, a 0.6 mm gap, 1.6 … 2.6 every 0.2, a 3 mm
  // gap, 5.6 … 7.0. The 0.6 mm gap (< 2R) leaves a cusp R − √(R² − 0.3²); the 3 mm gap is a band
  // no pass met: uncut, of width 3 − 2·√(2R·tol − tol²) (where the ball's flank rises above tol).
  const double R = 1, tol = 0.002;
  const GridSpec g{-0.005, -0.005, 0.01, 800, 800};  // cell centres on multiples of 0.01
  ZMap zm = ZMap::flat(g, 0.5);
  Program p = raster(-2, 10, 0.0, 0.2, 6, zero);
  for (const Program& q : {raster(-2, 10, 1.6, 0.2, 6, zero), raster(-2, 10, 5.6, 0.2, 8, zero)})
    p.items.insert(p.items.end(), q.items.begin(), q.items.end());
  machine(zm, p, tooling::Cutter::ball(2 * R));
  const auto design = design_window(g, 1, 7, 0.0, 7.0, zero);  // 6 mm along X
  MetricsOptions o;
  o.tolerance_mm = tol;
  o.cutter = tooling::Cutter::ball(2 * R);
  const auto m = surface_metrics(zm, design, o);
  EXPECT_NEAR(m.scallop_max_mm, R - std::sqrt(R * R - 0.09), 1e-9);  // the cusp at y = 1.3
  EXPECT_EQ(m.rest_area_mm2, 0);
  const double band = 3 - 2 * std::sqrt(2 * R * tol - tol * tol);
  EXPECT_NEAR(m.uncut_area_mm2, band * 6, 6 * 0.03);
  EXPECT_NEAR(m.remaining_area_mm2, m.uncut_area_mm2 + m.scallop_area_mm2 + m.rest_area_mm2, 1e-9);
  EXPECT_GT(m.scallop_area_mm2, 0.3 * 6);
  // Without the cutter all of it is uncut, and the scallop is the band's height, not a cusp's.
  o.cutter.reset();
  const auto plain = surface_metrics(zm, design, o);
  EXPECT_NEAR(plain.uncut_area_mm2, m.remaining_area_mm2, 1e-9);
  EXPECT_GT(plain.scallop_max_mm, 0.4);
}

TEST(ZMap, WithTheCutterAConcaveCornerTighterThanTheBallIsRestMaterial) {
  // A floor at 0 for x < 3 and a vertical wall up to a top at 5 for x ≥ 3. Passes along Y every
  // 0.1 mm: on the floor up to x = 1.99 (the ball next to the wall), on the top from 3. The ball
  // cannot reach the floor within R − √(2R·tol − tol²) of the wall: rest material, the same for
  // any program with this ball. Cusps of a 0.1 mm stepover (0.00125 mm) are under the tolerance.
  const double R = 1, tol = 0.002;
  const GridSpec g{-0.01, -0.01, 0.02, 250, 250};  // cell centres on multiples of 0.02
  ZMap zm = ZMap::flat(g, 6);
  machine(zm, corner_passes_along_y(R), tooling::Cutter::ball(2 * R));
  const std::vector<double> design = corner_design(g);
  MetricsOptions o;
  o.tolerance_mm = tol;
  o.cutter = tooling::Cutter::ball(2 * R);
  const auto m = surface_metrics(zm, design, o);
  EXPECT_FALSE(m.gouged);
  // The floor's last column (x = 2.98) straddles the wall: along the normal it is ~0. Length 2 mm
  // (101 rows of 0.02); the lattice (every 5th cell) blurs the band's edge by ≤ 0.05 mm.
  const double rest = (R + 0.01 - std::sqrt(2 * R * tol - tol * tol) - 0.02) * 101 * 0.02;
  EXPECT_NEAR(m.rest_area_mm2, rest, 0.06 * 101 * 0.02);
  EXPECT_NEAR(m.uncut_area_mm2, 0, 0.06 * 101 * 0.02);
  // No scallop but at the rest band's edge, which the same lattice blurs: -O2/-O3 builds classify
  // every cell there as rest, an -O1 build (no fused multiply-adds) two columns of it as scallop
  // (0.0808 mm², 0.00406 mm high); a stepover's cusps would be scallop all over the 2 × 2 mm floor.
  // Its height is at most the ball's rest height one lattice blur (0.05 mm) into the band: the ball
  // touches the floor a = √(2R·tol − tol²) from its axis, so R − √(R² − (a + 0.05)²) ≈ 0.0064 mm.
  EXPECT_LE(m.scallop_area_mm2, 0.06 * 101 * 0.02);
  const double a = std::sqrt(2 * R * tol - tol * tol);
  EXPECT_LE(m.scallop_max_mm, R - std::sqrt(R * R - (a + 0.05) * (a + 0.05)));
}

TEST(ZMap, TheRestTestsAnswersKeptForADesignGiveTheSameFiguresForEveryProgramAndCutter) {
  // The corner of the test above, machined by passes along Y and by passes along X, then with a
  // Ø1.5 ball along Y stopping where the Ø2 did (leaving a band it could reach: uncut, where the
  // Ø2's answers would call it rest): each program's figures with one ReachMemo shared by all three calls (the way a part's
  // strategies are scored) are those computed without it, bit for bit; the memo starts afresh for
  // the other cutter instead of handing it the Ø2's answers.
  const GridSpec g{-0.01, -0.01, 0.02, 250, 250};
  const std::vector<double> design = corner_design(g);
  Program across;  // along X, the floor's passes stopping 1.01 mm short of the wall
  for (int k = 0; k <= 90; ++k) {
    const double y = -2 + 0.1 * k;
    add(across, mv(Motion::Rapid, -2, y, 8));
    add(across, mv(Motion::Line, -2, y, 0));
    add(across, mv(Motion::Line, 1.99, y, 0));
    add(across, mv(Motion::Rapid, 1.99, y, 8));
    add(across, mv(Motion::Rapid, 3, y, 8));
    add(across, mv(Motion::Line, 3, y, 5));
    add(across, mv(Motion::Line, 7, y, 5));
    add(across, mv(Motion::Rapid, 7, y, 8));
  }
  const auto memo = std::make_shared<ReachMemo>();
  const std::vector<std::pair<Program, double>> runs{
      {corner_passes_along_y(1), 1}, {across, 1}, {corner_passes_along_y(1), 0.75}};
  for (const auto& [program, R] : runs) {
    ZMap zm = ZMap::flat(g, 6);
    machine(zm, program, tooling::Cutter::ball(2 * R));
    MetricsOptions o;
    o.ra_map = false;
    o.cutter = tooling::Cutter::ball(2 * R);
    const SurfaceMetrics alone = surface_metrics(zm, design, o);
    o.reach_memo = memo;
    const SurfaceMetrics shared = surface_metrics(zm, design, o);
    EXPECT_GT(alone.rest_area_mm2, 0.5);
    EXPECT_EQ(shared.rest_area_mm2, alone.rest_area_mm2);
    EXPECT_EQ(shared.scallop_area_mm2, alone.scallop_area_mm2);
    EXPECT_EQ(shared.uncut_area_mm2, alone.uncut_area_mm2);
    EXPECT_EQ(shared.scallop_max_mm, alone.scallop_max_mm);
  }
}

TEST(ZMap, FlatEndMillLeavesNoScallop) {
  const GridSpec g{0, 0, 0.02, 200, 200};
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-4, 8, -2, 1.0, 9, zero), tooling::Cutter::flat(4));
  const auto m = surface_metrics(zm, design_window(g, 1, 3, 1, 3, zero));
  const auto e = deviation(zm, design_window(g, 1, 3, 1, 3, zero));
  EXPECT_EQ(e[100 * g.nx + 100], 0);
  EXPECT_TRUE(std::isnan(e[0]));
  EXPECT_EQ(m.scallop_max_mm, 0);
  EXPECT_EQ(m.min_e_mm, 0);
  EXPECT_EQ(m.max_e_mm, 0);
  EXPECT_EQ(m.uncut_area_mm2, 0);
  EXPECT_NEAR(m.ra_median_um, 0, 1e-9);
}

TEST(ZMap, DipBelowDesignIsAGougeAtItsMove) {
  const GridSpec g{-0.005, -0.005, 0.01, 400, 400};
  ZMap zm = ZMap::flat(g, 0.5);
  Program p = raster(-2, 6, -1.0, 0.2, 31, zero);
  const std::size_t dip = p.items.size() + 2;  // the line that ends 0.05 below the plane
  add(p, mv(Motion::Rapid, -2, 2, 5));
  add(p, mv(Motion::Line, -2, 2, 0));
  add(p, mv(Motion::Line, 2, 2, -0.05));
  add(p, mv(Motion::Line, 6, 2, 0));
  add(p, mv(Motion::Rapid, 6, 2, 5));
  for (std::size_t i = 0; i < p.items.size(); ++i) p.source_line.push_back(100 + i);
  const auto res = machine(zm, p, tooling::Cutter::ball(2));
  EXPECT_TRUE(res.cutting_rapids.empty());
  const auto m = surface_metrics(zm, design_window(g, 0.5, 3.5, 0.5, 3.5, zero));
  EXPECT_TRUE(m.gouged);
  EXPECT_NEAR(m.max_gouge_mm, 0.05, 1e-9);
  ASSERT_TRUE(m.gouge_has_move);
  EXPECT_EQ(m.gouge_move.item, dip);
  EXPECT_EQ(m.gouge_move.line, 100 + dip);
  EXPECT_EQ(m.first_gouge_move.item, dip);
  EXPECT_EQ(m.gouge_cell, 200u * 400u + 200u);  // x = y = 2
}

TEST(ZMap, PlanarArcEqualsItsAnalyticGroove) {
  const GridSpec g{0, 0, 0.02, 500, 500};
  ZMap zm = ZMap::flat(g, 0);
  Program p;
  const double cx = 5, cy = 5, r0 = 3, z = -0.3, R = 1;
  add(p, mv(Motion::Rapid, cx + r0, cy, 5));
  add(p, mv(Motion::Line, cx + r0, cy, z));
  add(p, mv(Motion::ArcCCW, cx, cy + r0, z, cx, cy));  // quarter circle, 0 → 90°
  add(p, mv(Motion::Rapid, cx, cy + r0, 5));
  machine(zm, p, tooling::Cutter::ball(2 * R));
  std::size_t checked = 0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double dx = g.x(ix) - cx, dy = g.y(iy) - cy;
      if (dx <= 0 || dy <= 0) continue;  // angular sweep only: the groove of the torus part
      const double d = std::abs(std::hypot(dx, dy) - r0);
      const double expect = d < R ? std::min(0.0, z + ball_f(R, d)) : 0.0;
      ASSERT_NEAR(zm.at(ix, iy), expect, 1e-12);
      ++checked;
    }
  EXPECT_GT(checked, 10000u);
  // Everywhere: the lower envelope of densely sampled tool positions (an upper bound, close).
  const int n = 4000;
  for (std::size_t iy = 0; iy < g.ny; iy += 7)
    for (std::size_t ix = 0; ix < g.nx; ix += 7) {
      double brute = 0;
      for (int k = 0; k <= n; ++k) {
        const double th = std::numbers::pi / 2 * k / n;
        const double r = std::hypot(g.x(ix) - cx - r0 * std::cos(th), g.y(iy) - cy - r0 * std::sin(th));
        if (r <= R) brute = std::min(brute, z + ball_f(R, r));
      }
      // plunge at the start: the tip went from 5 down to z at (cx + r0, cy): covered by k = 0.
      EXPECT_LE(zm.at(ix, iy), brute + 1e-12);
      EXPECT_GE(zm.at(ix, iy), brute - 2e-3);
    }
}

TEST(ZMap, EverySweepMatchesDenseSampling) {
  const GridSpec g{0, 0, 0.05, 120, 100};
  const tooling::Cutter cutters[] = {tooling::Cutter::ball(2), tooling::Cutter::flat(2), tooling::Cutter::bull(2, 0.3),
                                     tooling::Cutter::drill(2)};
  const gcode::Point3 a{1.2, 1.1, -0.1}, b{4.7, 3.4, -0.9};
  for (const auto& c : cutters) {
    ZMap zm = ZMap::flat(g, 0);
    SweepOptions o;
    o.start = a;
    Program p;
    add(p, mv(Motion::Line, b[0], b[1], b[2]));
    machine(zm, p, c, o);
    const int n = 20000;
    double worst_up = 0, worst_down = 0;
    for (std::size_t iy = 0; iy < g.ny; iy += 3)
      for (std::size_t ix = 0; ix < g.nx; ix += 3) {
        double brute = 0;  // also where no sample is within reach: the map must be untouched there
        const double ex = g.x(ix) - a[0], ey = g.y(iy) - a[1], dx = b[0] - a[0], dy = b[1] - a[1];
        const double tc = std::clamp((ex * dx + ey * dy) / (dx * dx + dy * dy), 0.0, 1.0);
        const bool near = std::hypot(ex - tc * dx, ey - tc * dy) <= c.radius() + 1e-9;
        for (int k = 0; near && k <= n; ++k) {
          const double t = static_cast<double>(k) / n;
          const double r = std::hypot(g.x(ix) - a[0] - t * (b[0] - a[0]), g.y(iy) - a[1] - t * (b[1] - a[1]));
          const double f = profile_height(c, r);
          if (std::isfinite(f)) brute = std::min(brute, a[2] + t * (b[2] - a[2]) + f);
        }
        worst_up = std::max(worst_up, zm.at(ix, iy) - brute);
        worst_down = std::max(worst_down, brute - zm.at(ix, iy));
      }
    EXPECT_LT(worst_up, 1e-9) << static_cast<int>(c.type);    // never above a sampled position
    EXPECT_LT(worst_down, 2e-3) << static_cast<int>(c.type);  // sampling gap only
  }
}

// issue 36: `finish --tool bull:4:2` was accepted and `simulate --tool bull:4:2` refused it. The
// cutter's own check decides; a bull whose corner is its radius machines as the ball, bit for bit.
TEST(ZMap, ABullWithItsRadiusAsCornerMachinesAsTheBall) {
  const GridSpec g{0, 0, 0.05, 120, 100};
  Program p;
  add(p, mv(Motion::Line, 4.7, 3.4, -0.9));
  add(p, mv(Motion::ArcCCW, 2.7, 1.4, -0.9, 2.7, 3.4));
  SweepOptions o;
  o.start = {1.2, 1.1, -0.1};
  ZMap bull = ZMap::flat(g, 0), ball = ZMap::flat(g, 0);
  machine(bull, p, tooling::Cutter::bull(4, 2), o);
  machine(ball, p, tooling::Cutter::ball(4), o);
  for (std::size_t c = 0; c < g.cells(); ++c) ASSERT_EQ(bull.at(c % g.nx, c / g.nx), ball.at(c % g.nx, c / g.nx)) << c;
  EXPECT_THROW(machine(ball, p, tooling::Cutter::bull(4, 2.5), o), millnet::Error);
}

// A 118° drill plunged 3 mm leaves its cone: depth 3 at the axis, 3 − d / tan 59° at d.
TEST(ZMap, ADrillPlungeLeavesItsCone) {
  const GridSpec g{0, 0, 0.05, 200, 200};
  ZMap zm = ZMap::flat(g, 0);
  SweepOptions o;
  o.start = {5.025, 5.025, 1};
  Program p;
  add(p, mv(Motion::Line, 5.025, 5.025, -3));
  const tooling::Cutter d = tooling::Cutter::drill(6);
  machine(zm, p, d, o);
  const double k = 1 / std::tan(59 * std::numbers::pi / 180);
  for (const std::size_t off : {0UL, 10UL, 30UL, 55UL}) {
    const double r = static_cast<double>(off) * g.cell;
    EXPECT_NEAR(zm.at(100 + off, 100), -3 + r * k, 1e-12) << r;
  }
  EXPECT_EQ(zm.at(100 + 61, 100), 0);  // beyond R = 3 mm: untouched
}

TEST(ZMap, HelicalArcFollowsItsChords) {
  const GridSpec g{0, 0, 0.05, 200, 200};
  ZMap zm = ZMap::flat(g, 0);
  SweepOptions o;
  o.start = {8, 5, -0.1};
  Program p;
  add(p, mv(Motion::ArcCW, 5, 2, -0.6, 5, 5));  // quarter turn CW from (8,5) to (5,2), helical
  const auto res = machine(zm, p, tooling::Cutter::ball(2), o);
  EXPECT_GT(res.segments, 10u);
  const int n = 20000;
  double worst = 0;
  for (std::size_t iy = 0; iy < g.ny; iy += 3)
    for (std::size_t ix = 0; ix < g.nx; ix += 3) {
      double brute = 0;  // also where no sample is within reach: the map must be untouched there
      const double rho = std::hypot(g.x(ix) - 5, g.y(iy) - 5);
      const bool near = std::abs(rho - 3) <= 1 + 1e-9 && g.x(ix) >= 4 - 1e-9 && g.y(iy) <= 6 + 1e-9;
      for (int k = 0; near && k <= n; ++k) {
        const double t = static_cast<double>(k) / n, th = -std::numbers::pi / 2 * t;
        const double r = std::hypot(g.x(ix) - 5 - 3 * std::cos(th), g.y(iy) - 5 - 3 * std::sin(th));
        if (r <= 1) brute = std::min(brute, -0.1 - 0.5 * t + ball_f(1, r));
      }
      worst = std::max(worst, std::abs(zm.at(ix, iy) - brute));
    }
  EXPECT_LT(worst, 3e-3);
}

TEST(ZMap, RoughThenFinishReportsTheDepthOfCutTheFinisherMeets) {
  const GridSpec g{0, 0, 0.05, 200, 100};
  ZMap zm = ZMap::flat(g, 0);
  Program rough;  // flat Ø6 clears x < 5 down to z = −5
  for (double x = -2; x <= 2.01; x += 2) {
    add(rough, mv(Motion::Rapid, x, -4, 5));
    add(rough, mv(Motion::Line, x, -4, -5));
    add(rough, mv(Motion::Line, x, 9, -5));
    add(rough, mv(Motion::Rapid, x, 9, 5));
  }
  const auto r1 = machine(zm, rough, tooling::Cutter::flat(6));
  EXPECT_NEAR(r1.max_cut_mm[kLineKind], 5, 1e-12);
  Program fin;
  add(fin, mv(Motion::Rapid, 1.025, 2.525, 5));  // on cell centres
  add(fin, mv(Motion::Line, 1.025, 2.525, -5.1));
  add(fin, mv(Motion::Line, 9.025, 2.525, -5.1));
  add(fin, mv(Motion::Rapid, 9.025, 2.525, 5));
  const auto r2 = machine(zm, fin, tooling::Cutter::ball(2));
  EXPECT_NEAR(r2.max_cut_mm[kLineKind], 5.1, 1e-9);
  EXPECT_EQ(r2.max_cut_item[kLineKind], 2u);
  EXPECT_NEAR(r2.item_max_cut_mm[1], 0.1, 1e-9);  // the plunge lands in the roughed area
  EXPECT_EQ(r2.pass, 1u);
  MoveRef ref;
  ASSERT_TRUE(zm.origin(static_cast<std::size_t>(50) * g.nx + 20, ref));  // (1.025, 2.525): finish plunge area
  EXPECT_EQ(ref.pass, 1u);
  ASSERT_TRUE(zm.origin(static_cast<std::size_t>(10) * g.nx + 20, ref));  // (1.025, 0.525): roughing only
  EXPECT_EQ(ref.pass, 0u);
}

// The axial engagement (SweepResult::item_max_engage_mm) is what a tool's flutes meet: the stock
// above the tip where the cutter first reaches a cell. A ball shaving a wall's 0.5 mm skin from the
// top down removes the skin's whole 19 mm height at each cell, but meets it with its ball only; the
// same ball moving sideways into the wall meets all 19 mm at once.
TEST(ZMap, TheAxialEngagementIsWhatTheFlutesMeetNotTheHeightAMoveRemoves) {
  const GridSpec g{0, 0, 0.05, 200, 100};
  ZMap zm = ZMap::flat(g, 0);
  Program rough;  // flat Ø6 clears x < 4.5 down to z = −20: a wall at x = 4.5
  add(rough, mv(Motion::Rapid, 1.5, -2, 5));
  add(rough, mv(Motion::Line, 1.5, -2, -20));
  add(rough, mv(Motion::Line, 1.5, 9, -20));
  add(rough, mv(Motion::Rapid, 1.5, 9, 5));
  const auto r1 = machine(zm, rough, tooling::Cutter::flat(6));
  EXPECT_NEAR(r1.item_max_cut_mm[1], 20, 1e-12);
  EXPECT_NEAR(r1.item_max_cut_mm[2], 20, 1e-12);
  EXPECT_NEAR(r1.item_max_engage_mm[2], 20, 1e-12) << "sideways into the block: all of it";
  EXPECT_NEAR(r1.item_max_engage_mm[1], 3, 1e-12) << "a plunge: the cutter's radius (the tip meets the stock)";
  Program fin;  // Ø2 ball, axis 1 mm off x = 5: down the skin x ∈ [4.5, 5], then along +x at −19
  add(fin, mv(Motion::Rapid, 4.025, 2.525, 1));
  add(fin, mv(Motion::Line, 4.025, 2.525, -19));
  add(fin, mv(Motion::Line, 4.025 + 1e-3, 2.525, -19.1));  // a short step with an XY direction
  add(fin, mv(Motion::Line, 8.025, 2.525, -19.1));
  const auto r2 = machine(zm, fin, tooling::Cutter::ball(2));
  EXPECT_GT(r2.item_max_cut_mm[1], 18.5) << "the skin's height, removed at each of its cells";
  EXPECT_NEAR(r2.item_max_engage_mm[1], 1.0, 1e-9) << "met by the ball: its radius";
  EXPECT_LE(r2.item_max_engage_mm[2], 1.0 + 1e-9);
  EXPECT_NEAR(r2.item_max_engage_mm[3], 19.1, 1e-9) << "into the wall: the wall's height";
  EXPECT_NEAR(r2.item_max_cut_mm[3], 19.1, 1e-9);
  for (std::size_t i = 0; i < fin.items.size(); ++i) EXPECT_LE(r2.item_max_engage_mm[i], r2.item_max_cut_mm[i]);
}

TEST(ZMap, RapidsThatCutAreReported) {
  const GridSpec g{0, 0, 0.05, 100, 100};
  ZMap zm = ZMap::flat(g, 0);
  Program p;
  add(p, mv(Motion::Rapid, 1, 1, 5));
  add(p, mv(Motion::Rapid, 1, 1, -1));  // plunges at rapid
  add(p, mv(Motion::Line, 4, 1, -1));
  add(p, mv(Motion::Rapid, 4, 4, -1));  // traverses stock at rapid
  add(p, mv(Motion::Rapid, 4, 4, 5));
  const auto res = machine(zm, p, tooling::Cutter::flat(2));
  ASSERT_EQ(res.cutting_rapids.size(), 2u);
  EXPECT_EQ(res.cutting_rapids[0], 1u);
  EXPECT_EQ(res.cutting_rapids[1], 3u);
  EXPECT_NEAR(res.max_cut_mm[kRapidKind], 1, 1e-12);
}

TEST(ZMap, BitIdenticalWithOneAndTwoThreads) {
  const GridSpec g{0.003, -0.007, 0.013, 377, 311};
  Program p = raster(-1, 6, -1.3, 0.17, 35, tilted_tip);
  add(p, mv(Motion::Line, 3, 2, 0.2));
  add(p, mv(Motion::ArcCCW, 2, 3, 0.2, 2, 2));  // planar
  add(p, mv(Motion::ArcCW, 2, 1, -0.1, 2, 2));  // helical
  std::vector<double> design(g.cells());
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) design[iy * g.nx + ix] = tilted(g.y(iy)) - 0.01;
  for (const auto& c : {tooling::Cutter::ball(2), tooling::Cutter::bull(2, 0.4), tooling::Cutter::flat(1.5)}) {
    ZMap a = ZMap::flat(g, 3), b = ZMap::flat(g, 3);
    SweepOptions o1, o2;
    o1.threads = 1;
    o2.threads = 2;
    const auto ra = machine(a, p, c, o1);
    const auto rb = machine(b, p, c, o2);
    ASSERT_EQ(0, std::memcmp(a.heights().data(), b.heights().data(), g.cells() * sizeof(double)));
    ASSERT_EQ(a.stamps(), b.stamps());
    EXPECT_EQ(ra.item_max_cut_mm, rb.item_max_cut_mm);
    EXPECT_EQ(ra.cells_visited, rb.cells_visited);
    MetricsOptions m1, m2;
    m1.threads = 1;
    m2.threads = 2;
    const auto ma = surface_metrics(a, design, m1);
    const auto mb = surface_metrics(b, design, m2);
    ASSERT_EQ(0, std::memcmp(ma.ra_um.data(), mb.ra_um.data(), ma.ra_um.size() * sizeof(float)));
    EXPECT_EQ(ma.ra_median_um, mb.ra_median_um);
    EXPECT_EQ(ma.ra_share, mb.ra_share);
  }
}

TEST(ZMap, RefusesAGridAboveTheMemoryLimit) {
  const GridSpec huge{0, 0, 0.001, 100000, 100000};  // 1e10 cells
  EXPECT_THROW((void)ZMap::flat(huge, 0), Error);
  try {
    (void)ZMap::flat(huge, 0);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("above the limit"), std::string::npos) << e.what();
  }
  const GridSpec small{0, 0, 0.1, 100, 100};  // 120 kB
  EXPECT_THROW((void)ZMap::flat(small, 0, 100000), Error);
  EXPECT_NO_THROW((void)ZMap::flat(small, 0, 120000));
  EXPECT_THROW((void)ZMap::flat(GridSpec{0, 0, 0, 10, 10}, 0), Error);
  EXPECT_THROW((void)ZMap::from_heights(small, std::vector<double>(5, 0.0)), Error);
}

TEST(ZMap, StockFromHeightFieldAddsTheAllowance) {
  const GridSpec g{0, 0, 1, 3, 2};
  const ZMap zm = ZMap::from_heights(g, {0, 1, 2, kNaN, 4, 5}, 0.5, -3);
  EXPECT_EQ(zm.at(2, 0), 2.5);
  EXPECT_EQ(zm.at(0, 1), -3);
  EXPECT_EQ(zm.at(2, 1), 5.5);
}

// A stock made in the memory of a z-map already machined (a part's strategies one after another)
// is the stock made afresh: its heights, no stamps, no passes — and machining it again gives the
// same heights and stamps, stamps numbered from the first as on a fresh one. From a z-map of
// another grid too, and the reused one is left empty.
TEST(ZMap, AStockInTheMemoryOfAMachinedOneIsTheFreshStock) {
  const GridSpec g{0, 0, 0.1, 60, 40};
  std::vector<double> design(g.cells());
  for (std::size_t i = 0; i < design.size(); ++i) design[i] = i % 7 == 0 ? kNaN : -0.001 * static_cast<double>(i % 13);
  Program p;
  add(p, mv(Motion::Rapid, 1, 1, 1));
  add(p, mv(Motion::Line, 1, 1, -0.2));
  add(p, mv(Motion::Line, 5, 3, -0.3));
  const auto c = tooling::Cutter::ball(2);
  ZMap fresh = ZMap::from_heights(g, design, 0.1, -2);
  for (const GridSpec& before : {g, GridSpec{0, 0, 0.2, 10, 10}}) {
    ZMap used = ZMap::flat(before, 0.5);
    machine(used, p, c);
    ASSERT_EQ(used.passes(), 1U);
    ZMap again = ZMap::from_heights(g, design, 0.1, -2, kZMapMaxBytes, std::move(used));
    EXPECT_EQ(again.heights(), fresh.heights());
    EXPECT_EQ(again.stamps(), fresh.stamps());
    EXPECT_EQ(again.passes(), 0U);
    EXPECT_TRUE(used.heights().empty());  // NOLINT(bugprone-use-after-move): its memory was taken
    ZMap a = fresh, b = std::move(again);
    const SweepResult ra = machine(a, p, c), rb = machine(b, p, c);
    EXPECT_EQ(a.heights(), b.heights());
    EXPECT_EQ(a.stamps(), b.stamps());
    EXPECT_EQ(ra.item_max_cut_mm, rb.item_max_cut_mm);
    MoveRef ref;
    ASSERT_TRUE(b.origin(static_cast<std::size_t>(20 * g.nx + 30), ref));
    EXPECT_EQ(ref.item, 2U);  // the cut from (1, 1) to (5, 3) lowered the cell at (3.05, 2.05) last
  }
}

TEST(ZMap, PolylinesWithSharedJointsMatchDenseSampling) {
  // Up and down chords, valleys and peaks, a vertical move and a planar arc in the chain: the
  // joint spheres are applied once (half caps skipped) and the result must still be exact.
  const GridSpec g{0, 0, 0.04, 150, 120};
  const std::vector<gcode::Point3> pts{{0.5, 1.0, -0.2}, {1.5, 1.6, -0.5}, {2.1, 2.2, -0.1}, {2.8, 2.0, -0.4},
                                       {2.8, 2.0, -0.6}, {3.9, 2.9, -0.6}, {4.5, 2.6, -0.3}, {5.2, 3.3, -0.3}};
  for (const auto& c : {tooling::Cutter::ball(2), tooling::Cutter::flat(2), tooling::Cutter::bull(2, 0.35)}) {
    ZMap zm = ZMap::flat(g, 0);
    SweepOptions o;
    o.start = pts[0];
    Program p;
    for (std::size_t i = 1; i < pts.size(); ++i) add(p, mv(Motion::Line, pts[i][0], pts[i][1], pts[i][2]));
    add(p, mv(Motion::ArcCW, 5.2, 1.3, -0.3, 5.2, 2.3));  // half circle, planar
    add(p, mv(Motion::Line, 4.0, 0.9, -0.45));
    machine(zm, p, c, o);
    // Dense samples of the whole path, by piece; a piece whose XY box grown by the cutter's
    // radius misses a cell has no sample within reach of it (profile_height would be +∞).
    struct Piece {
      std::vector<gcode::Point3> q;
      double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
      void push(const gcode::Point3& v) {
        q.push_back(v);
        x0 = std::min(x0, v[0]);
        x1 = std::max(x1, v[0]);
        y0 = std::min(y0, v[1]);
        y1 = std::max(y1, v[1]);
      }
    };
    const double R = c.radius();
    std::vector<Piece> path;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      path.emplace_back();
      for (int k = 0; k < 4000; ++k) {
        const double t = k / 4000.0;
        path.back().push({pts[i][0] + t * (pts[i + 1][0] - pts[i][0]), pts[i][1] + t * (pts[i + 1][1] - pts[i][1]),
                          pts[i][2] + t * (pts[i + 1][2] - pts[i][2])});
      }
    }
    path.emplace_back();
    for (int k = 0; k <= 8000; ++k) {
      const double th = std::numbers::pi / 2 - std::numbers::pi * k / 8000.0;
      path.back().push({5.2 + std::cos(th), 2.3 + std::sin(th), -0.3});
    }
    path.emplace_back();
    for (int k = 1; k <= 4000; ++k) {
      const double t = k / 4000.0;
      path.back().push({5.2 - 1.2 * t, 1.3 - 0.4 * t, -0.3 - 0.15 * t});
    }
    double up = 0, down = 0;
    for (std::size_t iy = 0; iy < g.ny; iy += 2)
      for (std::size_t ix = 0; ix < g.nx; ix += 2) {
        double brute = 0;
        const double x = g.x(ix), y = g.y(iy);
        for (const Piece& pc : path) {
          if (x < pc.x0 - R || x > pc.x1 + R || y < pc.y0 - R || y > pc.y1 + R) continue;
          for (const auto& q : pc.q) {
            const double f = profile_height(c, std::hypot(x - q[0], y - q[1]));
            if (std::isfinite(f)) brute = std::min(brute, q[2] + f);
          }
        }
        up = std::max(up, zm.at(ix, iy) - brute);
        down = std::max(down, brute - zm.at(ix, iy));
      }
    EXPECT_LT(up, 1e-9) << static_cast<int>(c.type);
    EXPECT_LT(down, 2e-3) << static_cast<int>(c.type);
  }
}

// The exact lowest point of a Ø2R ball's bottoms over (px, py) along the line a → b, or +∞:
// h(t) = z(t) + R − √(R² − d(t)²) is convex on the interval where d(t) ≤ R, so a golden-section
// search over that interval finds its minimum (to 1e-13 in t), and the ends are tried as well.
double exact_ball_line(const gcode::Point3& a, const gcode::Point3& b, double R, double px, double py) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], wx = px - a[0], wy = py - a[1];
  const double l2 = dx * dx + dy * dy;
  double t0 = 0, t1 = 1;
  if (l2 > 0) {
    const double wd = wx * dx + wy * dy, disc = wd * wd - l2 * (wx * wx + wy * wy - R * R);
    if (disc < 0) return kInf;
    t0 = std::max(0.0, (wd - std::sqrt(disc)) / l2);
    t1 = std::min(1.0, (wd + std::sqrt(disc)) / l2);
    if (t0 > t1) return kInf;
  } else if (wx * wx + wy * wy > R * R) {
    return kInf;
  }
  auto h = [&](double t) {
    const double ex = wx - t * dx, ey = wy - t * dy;
    return a[2] + t * (b[2] - a[2]) + R - std::sqrt(std::max(R * R - ex * ex - ey * ey, 0.0));
  };
  const double g = (std::sqrt(5.0) - 1) / 2;
  double lo = t0, hi = t1, x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = h(x1), f2 = h(x2);
  while (hi - lo > 1e-13) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = h(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = h(x2);
    }
  }
  return std::min({f1, f2, h(t0), h(t1)});
}

TEST(ZMap, BallFinishingChordsOverCutStockMatchTheExactEnvelopeCellByCell) {
  // What a finishing path gives the kernel: chords of 0.13 mm (much shorter than the ball),
  // passes 0.2 mm apart in two directions, up and down a wavy surface, over stock that earlier
  // passes already cut. Each chord's rows are clipped to where it can be lowest and its shared
  // end spheres are applied once: cell by cell the map must still be the exact lowest sphere
  // bottom of all chords, against a per-chord golden-section minimum of the convex h(t).
  const double R = 1;
  const GridSpec g{0, 0, 0.02, 110, 100};
  auto surf = [](double x, double y) { return 0.25 * std::sin(1.9 * x + 0.8 * y) + 0.1 * std::cos(2.7 * y); };
  std::vector<std::pair<gcode::Point3, gcode::Point3>> chords;
  Program p;
  SweepOptions o;
  o.start = {-1.5, -1.0, 3};
  gcode::Point3 at = o.start;
  auto line_to = [&](Motion m, gcode::Point3 q) {
    add(p, mv(m, q[0], q[1], q[2]));
    if (m != Motion::Rapid) chords.push_back({at, q});
    at = q;
  };
  // Passes along X, then along a diagonal (34°), each zig-zagging through the window's centre
  // region, on the surface + R/4.
  for (int dir = 0; dir < 2; ++dir)
    for (int k = 0; k < 14; ++k) {
      const double off = -1.3 + 0.2 * k;
      const double ux = dir == 0 ? 1 : std::cos(0.6), uy = dir == 0 ? 0 : std::sin(0.6);
      const bool fwd = k % 2 == 0;
      const int n = 23;
      for (int i = 0; i <= n; ++i) {
        const double s = -1.5 + 0.13 * (fwd ? i : n - i);
        const double x = 1.1 + s * ux - off * uy, y = 1.0 + s * uy + off * ux;
        const gcode::Point3 q{x, y, surf(x, y) + 0.25};
        if (i == 0) line_to(Motion::Rapid, {x, y, 3});
        line_to(Motion::Line, q);  // the first: a plunge onto the pass
      }
      line_to(Motion::Rapid, {at[0], at[1], 3});
    }
  ZMap zm = ZMap::flat(g, 0.6);
  machine(zm, p, tooling::Cutter::ball(2 * R), o);
  double worst = 0;
  std::size_t cut = 0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      double e = 0.6;
      for (const auto& [a, b] : chords) {
        if (std::min(a[0], b[0]) - R > g.x(ix) || std::max(a[0], b[0]) + R < g.x(ix)) continue;
        if (std::min(a[1], b[1]) - R > g.y(iy) || std::max(a[1], b[1]) + R < g.y(iy)) continue;
        e = std::min(e, exact_ball_line(a, b, R, g.x(ix), g.y(iy)));
      }
      cut += e < 0.6 ? 1 : 0;
      worst = std::max(worst, std::abs(zm.at(ix, iy) - e));
    }
  EXPECT_GT(cut, g.cells() * 9 / 10);  // the passes cover the window
  EXPECT_LT(worst, 1e-7);
}

TEST(ZMap, TheRowBoundsLeaveRowsButChangeNoHeightStampOrCut) {
  // A finishing path of short chords, passes 0.15 mm apart along X and then along a diagonal, up
  // and down a wavy surface over stock cut by a first, higher raster: the rows each chord cannot
  // lower are left by the row bounds without a look at their cells. Swept with and without the
  // bounds (and on one and two threads), every height, stamp, depth of cut, engagement and cell
  // evaluation must be the same bits; with them, rows were left.
  const GridSpec g{-0.4, -0.3, 0.02, 160, 150};
  auto surf = [](double x, double y) { return 0.3 * std::sin(1.7 * x + 0.9 * y) + 0.1 * std::cos(3.1 * y); };
  Program p;
  auto passes = [&](double angle, double lift, int n) {
    for (int k = 0; k < n; ++k) {
      const double off = -1.0 + 0.15 * k, ux = std::cos(angle), uy = std::sin(angle);
      for (int i = 0; i <= 30; ++i) {
        const double s = -2.0 + 0.14 * (k % 2 == 0 ? i : 30 - i);
        const double x = 1.2 + s * ux - off * uy, y = 1.2 + s * uy + off * ux;
        if (i == 0) add(p, mv(Motion::Rapid, x, y, 3));
        add(p, mv(Motion::Line, x, y, surf(x, y) + lift));
      }
      add(p, mv(Motion::Rapid, 1.2, 1.2, 3));
    }
  };
  passes(0.0, 0.4, 12);  // the first, higher raster
  passes(0.0, 0.0, 18);
  passes(0.7, -0.02, 18);
  const tooling::Cutter ball = tooling::Cutter::ball(2);
  SweepOptions with, without, with1;
  with.threads = without.threads = 2;
  with1.threads = 1;
  without.row_bounds = false;
  ZMap a = ZMap::flat(g, 0.8), b = ZMap::flat(g, 0.8), c = ZMap::flat(g, 0.8);
  const SweepResult ra = machine(a, p, ball, with), rb = machine(b, p, ball, without), rc = machine(c, p, ball, with1);
  EXPECT_GT(ra.rows_bounded, 1000U);
  EXPECT_EQ(ra.rows_bounded, rc.rows_bounded);
  EXPECT_EQ(rb.rows_bounded, 0U);
  for (const ZMap* m : {&b, &c}) {
    ASSERT_EQ(0, std::memcmp(a.heights().data(), m->heights().data(), g.cells() * sizeof(double)));
    EXPECT_EQ(a.stamps(), m->stamps());
  }
  for (const SweepResult* r : {&rb, &rc}) {
    EXPECT_EQ(ra.item_max_cut_mm, r->item_max_cut_mm);
    EXPECT_EQ(ra.item_max_engage_mm, r->item_max_engage_mm);
    EXPECT_EQ(ra.cells_visited, r->cells_visited);
  }
  // And the map is the machined one: the last raster's lowest chord lies under the first's.
  double lowest = kInf;
  for (std::size_t i = 0; i < g.cells(); ++i) lowest = std::min(lowest, a.heights()[i]);
  EXPECT_LT(lowest, -0.3);
}

TEST(ZMap, TheScallopWalksTablesVisitTheCellsTheirCoordinatesGive) {
  // Passes on a plane at z = 0 along lines at 0°, 90°, 30°, 37° and 3-4-5 slopes, and concentric
  // arcs (whose across-feed direction turns cell by cell), spaced so that they leave cusps and,
  // between groups, uncut bands; the grid's origin and cell are not round. The split of the
  // material left into scallop, uncut and rest must be the same bits with the walks' tables and
  // with every step's cell computed from its coordinates, on one and two threads.
  const GridSpec g{-3.0137, -2.9911, 0.0173, 400, 390};
  std::vector<double> design(g.cells(), 0.0);
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix)
      if (std::hypot(g.x(ix) - 0.4, g.y(iy) + 0.2) < 0.3) design[iy * g.nx + ix] = kNaN;  // a hole
  for (const double angle : {0.0, 90.0, 30.0, 36.87, 53.130102354155978, 121.3}) {
    const double ux = std::cos(angle * std::numbers::pi / 180), uy = std::sin(angle * std::numbers::pi / 180);
    Program p;
    for (int k = 0; k < 24; ++k) {  // 0.23 mm apart, with a 1.3 mm gap after the 12th
      const double off = -3.4 + 0.23 * k + (k >= 12 ? 1.3 : 0);
      add(p, mv(Motion::Rapid, -5 * ux - off * uy, -5 * uy + off * ux, 3));
      add(p, mv(Motion::Line, -5 * ux - off * uy, -5 * uy + off * ux, 0));
      add(p, mv(Motion::Line, 5 * ux - off * uy, 5 * uy + off * ux, 0));
      add(p, mv(Motion::Rapid, 5 * ux - off * uy, 5 * uy + off * ux, 3));
    }
    if (angle == 0.0)
      for (int k = 1; k < 9; ++k) {  // and arcs about (1.1, 1.3), 0.29 mm apart, on the upper right
        const double r = 0.29 * k;
        add(p, mv(Motion::Rapid, 1.1 + r, 1.3, 3));
        add(p, mv(Motion::Line, 1.1 + r, 1.3, -0.01));
        add(p, mv(Motion::ArcCCW, 1.1 - r, 1.3, -0.01, 1.1, 1.3));
        add(p, mv(Motion::Rapid, 1.1 - r, 1.3, 3));
      }
    ZMap zm = ZMap::flat(g, 0.5);
    machine(zm, p, tooling::Cutter::ball(2));
    MetricsOptions o;
    o.ra_map = false;
    o.cutter = tooling::Cutter::ball(2);
    std::vector<SurfaceMetrics> runs;
    for (const bool tables : {true, false})
      for (const int threads : {1, 2}) {
        o.walk_tables = tables;
        o.threads = threads;
        runs.push_back(surface_metrics(zm, design, o));
      }
    SCOPED_TRACE(angle);
    EXPECT_GT(runs[0].scallop_area_mm2, 5.0);
    EXPECT_GT(runs[0].uncut_area_mm2, 1.0);
    for (const SurfaceMetrics& m : runs) {
      EXPECT_EQ(m.scallop_area_mm2, runs[0].scallop_area_mm2);
      EXPECT_EQ(m.uncut_area_mm2, runs[0].uncut_area_mm2);
      EXPECT_EQ(m.rest_area_mm2, runs[0].rest_area_mm2);
      EXPECT_EQ(m.scallop_max_mm, runs[0].scallop_max_mm);
    }
  }
}

TEST(ZMap, RaOfAScallopedPlaneMatchesTheProfileIntegral) {
  const double p = 0.2, R = 1;
  const GridSpec g{-0.005, -0.005, 0.01, 400, 400};
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-2, 6, -1.0, p, 31, zero), tooling::Cutter::ball(2 * R));
  const auto m = surface_metrics(zm, design_window(g, 1, 3, 1, 3, zero));
  // Ra of the periodic scallop profile e(y) = R − √(R² − d²), d = distance to the nearest pass.
  const int n = 200000;
  double mean = 0;
  std::vector<double> e(n);
  for (int k = 0; k < n; ++k) {
    const double d = std::abs((k + 0.5) / n * p - p / 2);
    e[static_cast<std::size_t>(k)] = R - std::sqrt(R * R - (p / 2 - d) * (p / 2 - d));
    mean += e[static_cast<std::size_t>(k)] / n;
  }
  double ra = 0;
  for (double v : e) ra += std::abs(v - mean) / n;
  EXPECT_NEAR(m.ra_median_um, 1000 * ra, 0.03 * 1000 * ra);
  EXPECT_NEAR(m.ra_p90_um, 1000 * ra, 0.05 * 1000 * ra);
  EXPECT_NEAR(m.ra_mean_um, 1000 * ra, 0.05 * 1000 * ra);
}

TEST(ZMap, RaStrideKeepsTheLatticeCellsBitForBitAndLeavesTheRestNaN) {
  const double p = 0.2, R = 1;
  const GridSpec g{-0.005, -0.005, 0.01, 400, 400};
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-2, 6, -1.0, p, 31, zero), tooling::Cutter::ball(2 * R));
  const auto design = design_window(g, 1, 3, 1, 3, zero);
  const auto full = surface_metrics(zm, design);
  MetricsOptions o;
  o.ra_every = 5;
  const auto thin = surface_metrics(zm, design, o);
  std::size_t lattice = 0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const std::size_t i = iy * g.nx + ix;
      if (ix % 5 == 2 && iy % 5 == 2) {
        if (!std::isnan(full.ra_um[i])) ++lattice;
        EXPECT_EQ(std::memcmp(&thin.ra_um[i], &full.ra_um[i], sizeof(float)), 0) << ix << "," << iy;
      } else {
        EXPECT_TRUE(std::isnan(thin.ra_um[i])) << ix << "," << iy;
      }
    }
  EXPECT_EQ(thin.ra_cells, lattice);
  EXPECT_NEAR(static_cast<double>(thin.ra_cells) * 25, static_cast<double>(full.ra_cells),
              0.05 * static_cast<double>(full.ra_cells));
  EXPECT_NEAR(thin.ra_median_um, full.ra_median_um, 0.02 * full.ra_median_um);
  // Everything but the Ra map is the same.
  EXPECT_EQ(thin.max_gouge_mm, full.max_gouge_mm);
  EXPECT_EQ(thin.scallop_max_mm, full.scallop_max_mm);
  EXPECT_EQ(thin.uncut_area_mm2, full.uncut_area_mm2);
  o.ra_every = 0;
  EXPECT_THROW((void)surface_metrics(zm, design, o), Error);
}

TEST(ZMap, AGougeIsMeasuredAlongTheSurfaceNormal) {
  // Design z = x·tan 60° over a 2 × 2 mm window; the machined surface 0.01 mm lower everywhere
  // (vertically): 0.01·cos 60° = 0.005 mm deep along the normal. On flat ground the two agree.
  const GridSpec g{0, 0, 0.01, 200, 200};
  const double t = std::tan(std::numbers::pi / 3);
  std::vector<double> design(g.cells());
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) design[iy * g.nx + ix] = g.x(ix) * t;
  const ZMap low = ZMap::from_heights(g, design, -0.01);
  MetricsOptions o;
  o.ra_map = false;
  o.tolerance_mm = 0.004;
  auto m = surface_metrics(low, design, o);
  EXPECT_NEAR(m.min_e_mm, -0.01, 1e-12);
  EXPECT_NEAR(m.max_gouge_mm, 0.005, 1e-9);
  EXPECT_TRUE(m.gouged);
  o.tolerance_mm = 0.006;
  EXPECT_FALSE(surface_metrics(low, design, o).gouged);
  std::vector<double> flat(g.cells(), 1.0);
  m = surface_metrics(ZMap::from_heights(g, flat, -0.01), flat, o);
  EXPECT_NEAR(m.max_gouge_mm, 0.01, 1e-12);
}

// Surface left at the stock is "not machined", never Ra 0 (issue 37 §1): a raster over the lower
// part of the window leaves its upper 57 % untouched — by hand: passes up to y = 1, a Ø2 ball at Z 0
// lowers the 0.5 mm stock within √(1 − 0.5²) = 0.866 mm of its path, so y > 1.866 of [1, 3] stays.
// Those cells have no Ra; the statistics are the machined cells' (the scallop's Ra, not 0).
TEST(ZMap, SurfaceLeftAtTheStockIsNotMachinedNotSmooth) {
  const double p = 0.2, R = 1;
  const GridSpec g{-0.005, -0.005, 0.01, 400, 400};
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-2, 6, -1.0, p, 11, zero), tooling::Cutter::ball(2 * R));  // y = -1 … 1
  const auto m = surface_metrics(zm, design_window(g, 1, 3, 1, 3, zero));
  const double untouched = (3 - (1 + std::sqrt(R * R - 0.25))) / 2;  // 0.567
  EXPECT_NEAR(m.ra_not_machined_share, untouched, 0.01);
  EXPECT_EQ(m.ra_cells + m.not_machined_cells, m.surface_cells);
  double share = m.ra_not_machined_share;
  for (double s : m.ra_share) share += s;
  EXPECT_NEAR(share, 1, 1e-12);
  // Without the rule the median would be 0 (most cells flat at the stock): it is the scallop's.
  EXPECT_GT(m.ra_median_um, 0.5);
}

// Issue 37 §2: the share of a surface in specification, by hand. A Ø2 ball's raster on a plane,
// passes p apart, leaves at distance d from a pass the height R − √(R² − d²): with the limit
// L = scallop + form tolerance, the cells with d > d* = √(R² − (R − L)²) are over it.
TEST(ZMap, TheShareInSpecOfABallRasterIsTheShareOfItsCuspsUnderTheLimit) {
  const double R = 1, L = 0.010, cell = 0.004;
  const GridSpec g{-0.5 * cell, -0.5 * cell, cell, 875, 875};  // centres on multiples of 0.004, to 3.5 mm
  MetricsOptions o;
  o.cutter = tooling::Cutter::ball(2 * R);
  o.spec_limit_mm = L;
  o.ra_map = false;
  const double d_star = std::sqrt(R * R - (R - L) * (R - L));  // 0.14107 mm
  // Passes 0.3 apart: cusps 0.0113 mm > L; over the limit on 2·(0.15 − d*) of every 0.3 mm.
  ZMap wide = ZMap::flat(g, 0.5);
  machine(wide, raster(-2, 6, -1.15, 0.3, 20, zero), tooling::Cutter::ball(2 * R));  // cusps on cell centres
  const auto m = surface_metrics(wide, design_window(g, 1, 3, 1, 3, zero), o);
  ASSERT_TRUE(m.spec_measured);
  EXPECT_EQ(m.spec_cells, m.surface_cells);  // a plane: no rest material
  EXPECT_EQ(m.in_spec_cells + m.over_spec_cells + m.spec_not_machined_cells, m.spec_cells);
  EXPECT_EQ(m.spec_not_machined_cells, 0u);
  const double over = 2 * (0.15 - d_star) / 0.3;  // 0.0596
  EXPECT_NEAR(1 - m.spec_share, over, 2 * cell / 0.3);
  EXPECT_NEAR(m.over_spec_max_mm, R - std::sqrt(R * R - 0.15 * 0.15), 1e-9);  // the cusp, 0.01131 mm
  // Passes 0.2 apart (the spec's spacing for a 0.005 mm scallop): all of it in spec.
  ZMap fine = ZMap::flat(g, 0.5);
  machine(fine, raster(-2, 6, -1.2, 0.2, 30, zero), tooling::Cutter::ball(2 * R));
  const auto f = surface_metrics(fine, design_window(g, 1, 3, 1, 3, zero), o);
  EXPECT_EQ(f.spec_share, 1.0);
  EXPECT_EQ(f.over_spec_cells, 0u);
}

// Surface the passes never reach is "not machined", never in spec; the ball's flank at the end of
// the passes is over the limit. Passes end at x = 2; the design runs to x = 3.4 over a stock 0.5 mm
// above it. Beyond x = 2 a cell at dy from the nearest pass (|dy| ≤ 0.1) is in spec to
// x − 2 = √(d*² − dy²), and cut at all to √(r² − dy²), r = √(R² − (R − 0.5)²) where the flank
// leaves the stock: over the limit between, not machined beyond. Averaged over dy, the reach of a
// radius r is (1/0.2)∫√(r² − t²) dt over [−0.1, 0.1].
TEST(ZMap, SurfaceThePassesNeverReachIsNotMachinedAndNotInSpec) {
  const double R = 1, L = 0.010, cell = 0.0025;
  const GridSpec g{-0.5 * cell, -0.5 * cell, cell, 1400, 1400};
  ZMap zm = ZMap::flat(g, 0.5);
  machine(zm, raster(-2, 2, -1.2, 0.2, 30, zero), tooling::Cutter::ball(2 * R));
  MetricsOptions o;
  o.spec_limit_mm = L;  // without the cutter: every surface cell judged
  o.ra_map = false;
  const auto m = surface_metrics(zm, design_window(g, 1, 3.4, 1, 3, zero), o);
  auto reach = [](double r) {  // (1/0.2)·∫_{−0.1}^{0.1} √(r² − t²) dt, r ≥ 0.1
    auto F = [r](double t) { return 0.5 * (t * std::sqrt(r * r - t * t) + r * r * std::asin(t / r)); };
    return (F(0.1) - F(-0.1)) / 0.2;
  };
  const double d_star = reach(std::sqrt(R * R - (R - L) * (R - L)));     // 0.1281 mm
  const double flank = reach(std::sqrt(R * R - (R - 0.5) * (R - 0.5)));  // 0.8641 mm
  const double width = 2.4, n = static_cast<double>(m.spec_cells);
  EXPECT_NEAR(m.spec_share, (1 + d_star) / width, 2 * cell / width);
  EXPECT_NEAR(static_cast<double>(m.over_spec_cells) / n, (flank - d_star) / width, 2 * cell / width);
  EXPECT_NEAR(static_cast<double>(m.spec_not_machined_cells) / n, (1.4 - flank) / width, 2 * cell / width);
  EXPECT_LT(m.over_spec_max_mm, 0.5);  // nearly the stock's full allowance, just inside the flank
  EXPECT_GT(m.over_spec_max_mm, 0.49);
  EXPECT_GT(g.x(m.over_spec_cell % g.nx), 2 + d_star);
}

// Material over a threshold, along the normal (area_above_mm2, cells_above): a 45° plane
// z = x over 40 × 20 cells of 0.1 mm, its stock raised vertically by 0.03 mm on the left half
// (0.03·cos 45° = 0.0212 mm along the normal) and by 0.025 mm on the right (0.0177 mm): with
// t = 0.02 only the left half counts, 20 × 20 cells = 4 mm²; with t = 0.015 all of it, 8 mm².
TEST(ZMap, TheAreaOverAThicknessCountsTheMaterialAlongTheNormal) {
  const GridSpec g{0.05, 0.05, 0.1, 40, 20};
  std::vector<double> design(g.cells()), stock(g.cells());
  for (std::size_t i = 0; i < g.cells(); ++i) {
    design[i] = g.x(i % g.nx);
    stock[i] = design[i] + (i % g.nx < 20 ? 0.03 : 0.025);
  }
  const ZMap z = ZMap::from_heights(g, stock);
  EXPECT_NEAR(area_above_mm2(z, design, 0.02), 4.0, 1e-9);
  EXPECT_NEAR(area_above_mm2(z, design, 0.015), 8.0, 1e-9);
  const std::vector<std::uint8_t> cells = cells_above(z, design, 0.02);
  EXPECT_EQ(std::count(cells.begin(), cells.end(), 1), 400);
  EXPECT_EQ(cells[5], 1);
  EXPECT_EQ(cells[25], 0);
  // Only the cells asked for; off the surface (NaN) never.
  std::vector<std::uint8_t> only(g.cells(), 0);
  for (std::size_t i = 0; i < g.cells(); i += 2) only[i] = 1;
  EXPECT_NEAR(area_above_mm2(z, design, 0.02, only), 2.0, 1e-9);
  design[0] = std::nan("");
  EXPECT_NEAR(area_above_mm2(z, design, 0.02), 3.99, 1e-9);
  EXPECT_THROW((void)area_above_mm2(z, std::vector<double>(3, 0.0), 0.02), Error);
}
