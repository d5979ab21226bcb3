// The exact gouge check (issue 37 §1): parts built here with walls, bores, a boss and an open patch
// whose edges lie exactly on z-map cell centres, where the z-map reports a gouge that the tool never
// cut; the exact check refutes them, and finds a real plunge 0.5 mm into a flat top at its line.
// Hand-computed values only (cell 0.25 mm, all coordinates exact in binary).
#include "millnet/simulate/exact_gouge.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/simulate/maps.hpp"
#include "millnet/simulate/zmap.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>

using namespace millnet;
using namespace millnet::simulate;
using gcode::Motion;
using gcode::Move;
using gcode::Program;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Columns over the breakpoints xs × ys, column (i, j) at height h[j][i] (NaN: no material), top
/// quads, vertical walls between columns of different heights and around the outside down to
/// `bottom` (walls = false: the tops only, an open patch).
ingest::Mesh columns(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<std::vector<double>>& h, double bottom, bool walls = true) {
  ingest::Mesh m;
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;
  auto quad = [&](std::array<double, 3> a, std::array<double, 3> b, std::array<double, 3> c, std::array<double, 3> d) {
    const int k = static_cast<int>(v.size());
    v.insert(v.end(), {a, b, c, d});
    f.push_back({k, k + 1, k + 2});
    f.push_back({k, k + 2, k + 3});
  };
  const std::size_t nx = xs.size() - 1, ny = ys.size() - 1;
  auto at = [&](long i, long j) {
    if (i < 0 || j < 0 || i >= static_cast<long>(nx) || j >= static_cast<long>(ny)) return kNaN;
    return h[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)];
  };
  for (long j = 0; j < static_cast<long>(ny); ++j)
    for (long i = 0; i < static_cast<long>(nx); ++i) {
      const double x0 = xs[static_cast<std::size_t>(i)], x1 = xs[static_cast<std::size_t>(i) + 1];
      const double y0 = ys[static_cast<std::size_t>(j)], y1 = ys[static_cast<std::size_t>(j) + 1];
      const double z = at(i, j);
      if (!std::isnan(z)) quad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z});
      if (!walls) continue;
      // walls on the column's +x and +y sides (and on -x, -y at the border), between both heights
      auto wall = [&](double za, double zb, std::array<double, 2> p, std::array<double, 2> q) {
        const double lo = std::isnan(za) ? bottom : za, hi = std::isnan(zb) ? bottom : zb;
        if (std::isnan(za) && std::isnan(zb)) return;
        if (lo == hi) return;
        const double a = std::min(lo, hi), b = std::max(lo, hi);
        quad({p[0], p[1], a}, {q[0], q[1], a}, {q[0], q[1], b}, {p[0], p[1], b});
      };
      wall(z, at(i + 1, j), {x1, y0}, {x1, y1});
      wall(z, at(i, j + 1), {x0, y1}, {x1, y1});
      if (i == 0) wall(z, kNaN, {x0, y0}, {x0, y1});
      if (j == 0) wall(z, kNaN, {x0, y0}, {x1, y0});
    }
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) m.V(static_cast<Eigen::Index>(i), k) = v[i][static_cast<std::size_t>(k)];
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(i), k) = f[i][static_cast<std::size_t>(k)];
  return m;
}

/// The plate of the tests, 20 × 20 mm, top Z 0, bottom Z −10: a through-bore [8.125, 11.875]²,
/// a blind bore [3.125, 6.125]² with its floor at Z −5, a boss [14.125, 17.125]² up to Z +5. Every
/// wall lies on a line of cell centres of the 0.25 mm grid below.
ingest::Mesh plate() {
  const std::vector<double> b{0, 3.125, 6.125, 8.125, 11.875, 14.125, 17.125, 20};
  std::vector<std::vector<double>> h(7, std::vector<double>(7, 0.0));
  h[3][3] = kNaN;  // through-bore
  h[1][1] = -5;    // blind bore
  h[5][5] = 5;     // boss
  return columns(b, b, h, -10);
}

/// An open patch at Z 0 over [0, 10.125] × [0, 20]: no walls, no solid below.
ingest::Mesh patch() { return columns({0, 10.125}, {0, 20}, {{0.0}}, -10, false); }

const GridSpec kGrid{0, 0, 0.25, 80, 80};

std::vector<double> design_of(const ingest::Mesh& mesh) {
  const ingest::HeightField hf = ingest::rasterize_top(mesh, 0.125, 0.125, 0.25, 80, 80);
  return design_heights(hf, 0);
}

Move mv(Motion m, double x, double y, double z) {
  Move v;
  v.motion = m;
  v.to = {x, y, z};
  v.feed = m == Motion::Rapid ? 0 : 600;
  return v;
}

/// Rapid above (x, y), feed down to z, then along to (x2, y2, z), rapid up; lines 11, 12, 13, 14.
Program plunge_and_run(double x, double y, double z, double x2, double y2) {
  Program p;
  p.items = {mv(Motion::Rapid, x, y, 8), mv(Motion::Line, x, y, z), mv(Motion::Line, x2, y2, z),
             mv(Motion::Rapid, x2, y2, 8)};
  p.source_line = {11, 12, 13, 14};
  return p;
}

struct Checked {
  SurfaceMetrics zmap;   ///< what the z-map alone says
  SurfaceMetrics exact;  ///< after confirm_gouges
};

Checked machine_and_check(const ingest::Mesh& mesh, const Program& p, const tooling::Cutter& c) {
  const std::vector<double> design = design_of(mesh);
  ZMap z = ZMap::flat(kGrid, 6.0);  // above the boss: every cell below the design was cut there
  (void)machine(z, p, c);
  MetricsOptions mo;
  mo.ra_map = false;
  Checked r;
  r.zmap = surface_metrics(z, design, mo);
  r.exact = r.zmap;
  const PartSolid solid(mesh, 0);
  confirm_gouges(r.exact, z, design, solid, {{&p, c}}, ExactGougeOptions{});
  return r;
}

}  // namespace

// A Ø2 ball plunged in the through-bore 1 mm from its wall (x = 8.125) to Z −5: its side touches
// the wall, the cells on the bore's edge (design Z 0, the bore beside them empty) are cut to −4.
TEST(ExactGouge, ThroughBoreWallIsNoGougeWhereTheZMapReportsOne) {
  const Checked r = machine_and_check(plate(), plunge_and_run(9.125, 10, -5, 9.125, 10.5), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);  // the old behaviour: a 4 mm "gouge" at the bore's edge
  EXPECT_NEAR(r.zmap.max_gouge_mm, 4.0, 1e-9);
  EXPECT_TRUE(r.exact.gouge_checked);
  EXPECT_FALSE(r.exact.gouged);
  EXPECT_LE(r.exact.max_gouge_mm, 0.002);
  EXPECT_GE(r.exact.gouge_places_refuted, 1u);
  EXPECT_EQ(r.exact.gouge_places_refuted, r.exact.gouge_places_checked);
  EXPECT_NEAR(r.exact.zmap_max_gouge_mm, 4.0, 1e-9);
}

// The same ball on the blind bore's floor (Z −5), 1 mm from its wall at x = 3.125.
TEST(ExactGouge, BlindBoreWallAndFloorAreNoGouge) {
  const Checked r = machine_and_check(plate(), plunge_and_run(4.125, 4.5, -5, 4.125, 5), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);
  EXPECT_FALSE(r.exact.gouged);
  EXPECT_LE(r.exact.max_gouge_mm, 0.002);
  EXPECT_GE(r.exact.gouge_places_refuted, 1u);
}

// Along the boss's wall (x = 14.125) on the plate (Z 0), the ball's side touching the wall.
TEST(ExactGouge, BossVerticalWallIsNoGouge) {
  const Checked r = machine_and_check(plate(), plunge_and_run(13.125, 14.5, 0, 13.125, 16.5), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);
  EXPECT_FALSE(r.exact.gouged);
  EXPECT_LE(r.exact.max_gouge_mm, 0.002);
}

// Beside the open patch's edge (x = 10.125), below it: the ball's side meets the material under
// the edge only at one line.
TEST(ExactGouge, OpenPatchEdgeIsNoGouge) {
  const Checked r = machine_and_check(patch(), plunge_and_run(11.125, 5, -5, 11.125, 6), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);
  EXPECT_NEAR(r.zmap.max_gouge_mm, 4.0, 1e-9);
  EXPECT_FALSE(r.exact.gouged);
  EXPECT_LE(r.exact.max_gouge_mm, 0.002);
}

// A Ø2 ball plunged to Z −0.5 into the plate's flat top at (1.5, 10): 0.5 mm deep, on line 12
// (the plunge), where the z-map says the same.
TEST(ExactGouge, RealPlungeIsConfirmedWithItsDepthLineAndXY) {
  const Checked r = machine_and_check(plate(), plunge_and_run(1.5, 10, -0.5, 1.5, 10), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);
  ASSERT_TRUE(r.exact.gouged);
  EXPECT_NEAR(r.exact.max_gouge_mm, 0.5, 5e-4);
  EXPECT_EQ(r.exact.first_gouge_move.line, 12u);
  EXPECT_NEAR(r.exact.gouge_x_mm, 1.5, 1e-9);
  EXPECT_NEAR(r.exact.gouge_y_mm, 10, 1e-9);
  EXPECT_EQ(r.exact.gouge_places_refuted, 0u);
}

// Two programs on one z-map, each its pass: the first runs the ball along the through-bore's wall
// (a 4 mm z-map "gouge" the exact check refutes), the second plunges 0.5 mm into the top. Per
// pass: the first's real penetration (≤ the tolerance), the second's 0.5 mm; a third pass that
// cuts nothing gouges 0. Without a z-map gouge, the z-map's own per-pass figures.
TEST(ExactGouge, EachPassCarriesItsOwnDeepestGouge) {
  const ingest::Mesh mesh = plate();
  const std::vector<double> design = design_of(mesh);
  const tooling::Cutter c = tooling::Cutter::ball(2);
  const Program wall = plunge_and_run(9.125, 10, -5, 9.125, 10.5), dip = plunge_and_run(1.5, 10, -0.5, 1.5, 10),
                air = plunge_and_run(1.5, 4, 7, 1.5, 5);
  ZMap z = ZMap::flat(kGrid, 6.0);
  for (const Program* p : {&wall, &dip, &air}) (void)machine(z, *p, c);
  MetricsOptions mo;
  mo.ra_map = false;
  SurfaceMetrics m = surface_metrics(z, design, mo);
  confirm_gouges(m, z, design, PartSolid(mesh, 0), {{&wall, c}, {&dip, c}, {&air, c}}, ExactGougeOptions{});
  ASSERT_EQ(m.pass_max_gouge_mm.size(), 3u);
  EXPECT_LE(m.pass_max_gouge_mm[0], 0.002);
  EXPECT_GE(m.pass_max_gouge_mm[0], 0.0);
  EXPECT_NEAR(m.pass_max_gouge_mm[1], 0.5, 5e-4);
  EXPECT_EQ(m.pass_max_gouge_mm[2], 0.0);
  EXPECT_NEAR(m.max_gouge_mm, 0.5, 5e-4);
  // The plate's top skimmed 0.001 mm deep (within the tolerance): no exact check, the z-map's.
  ZMap skim = ZMap::flat(kGrid, 6.0);
  const Program top = plunge_and_run(1.625, 10.125, -0.001, 3.625, 10.125);  // over cell centres
  (void)machine(skim, top, c);
  SurfaceMetrics n = surface_metrics(skim, design, mo);
  confirm_gouges(n, skim, design, PartSolid(mesh, 0), {{&top, c}}, ExactGougeOptions{});
  EXPECT_FALSE(n.gouge_checked) << n.min_e_mm;
  EXPECT_NEAR(n.min_e_mm, -0.001, 1e-9);
  ASSERT_EQ(n.pass_max_gouge_mm.size(), 1u);
  EXPECT_NEAR(n.pass_max_gouge_mm[0], 0.001, 1e-9);
}

// The z-map's gouge places are gathered over chunks of cells in parallel: on a 0.05 mm grid of the
// plate (160,000 cells, three chunks), plunges 0.3, 0.5 and 0.2 mm deep at rows in each chunk
// (three passes) and a pass along the through-bore's wall (a z-map "gouge" the check refutes).
// Per pass the depth by hand, the wall's within the tolerance; on one thread and on two, every
// figure the same bits.
TEST(ExactGouge, ThePlacesGatheredInChunksGiveTheSameFiguresOnAnyThreadCount) {
  const ingest::Mesh mesh = plate();
  const GridSpec g{0, 0, 0.05, 400, 400};
  const std::vector<double> design = design_heights(ingest::rasterize_top(mesh, 0.025, 0.025, 0.05, 400, 400), 0);
  const tooling::Cutter c = tooling::Cutter::ball(2);
  const Program a = plunge_and_run(1.5, 2.0, -0.3, 1.5, 2.0), b = plunge_and_run(1.5, 10, -0.5, 1.5, 10),
                d = plunge_and_run(18.5, 19, -0.2, 18.5, 19), wall = plunge_and_run(9.125, 10, -5, 9.125, 10.5);
  ZMap z = ZMap::flat(g, 6.0);
  for (const Program* p : {&a, &b, &d, &wall}) (void)machine(z, *p, c);
  MetricsOptions mo;
  mo.ra_map = false;
  const SurfaceMetrics zmap = surface_metrics(z, design, mo);
  std::vector<SurfaceMetrics> runs;
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    SurfaceMetrics m = zmap;
    confirm_gouges(m, z, design, PartSolid(mesh, 0), {{&a, c}, {&b, c}, {&d, c}, {&wall, c}}, ExactGougeOptions{});
    runs.push_back(m);
  }
  omp_set_num_threads(2);
  const SurfaceMetrics& m = runs[0];
  ASSERT_TRUE(m.gouged);
  ASSERT_EQ(m.pass_max_gouge_mm.size(), 4u);
  EXPECT_NEAR(m.pass_max_gouge_mm[0], 0.3, 5e-4);
  EXPECT_NEAR(m.pass_max_gouge_mm[1], 0.5, 5e-4);
  EXPECT_NEAR(m.pass_max_gouge_mm[2], 0.2, 5e-4);
  EXPECT_LE(m.pass_max_gouge_mm[3], 0.002);
  EXPECT_NEAR(m.max_gouge_mm, 0.5, 5e-4);
  EXPECT_NEAR(m.gouge_x_mm, 1.5, 1e-9);
  EXPECT_NEAR(m.gouge_y_mm, 10, 1e-9);
  EXPECT_GE(m.zmap_gouge_places, 4u);
  EXPECT_GE(m.gouge_places_refuted, 1u);
  const SurfaceMetrics& n = runs[1];
  EXPECT_EQ(n.pass_max_gouge_mm, m.pass_max_gouge_mm);
  EXPECT_EQ(n.max_gouge_mm, m.max_gouge_mm);
  EXPECT_EQ(n.zmap_gouge_places, m.zmap_gouge_places);
  EXPECT_EQ(n.gouge_places_checked, m.gouge_places_checked);
  EXPECT_EQ(n.gouge_places_refuted, m.gouge_places_refuted);
  EXPECT_EQ(n.gouge_x_mm, m.gouge_x_mm);
  EXPECT_EQ(n.gouge_y_mm, m.gouge_y_mm);
  EXPECT_EQ(n.first_gouge_move.line, m.first_gouge_move.line);
  EXPECT_EQ(n.first_gouge_move.pass, m.first_gouge_move.pass);
}

// Penetration at one position, by hand: a ball 0.3 mm into the top; a flat Ø4 whose rim stands
// 0.5 mm over the boss's edge, 0.2 mm below its top (Z 4.8): 0.2 mm, while beside it, it is clear;
// a bull Ø4 r1 on the plate at Z −0.1: 0.1 mm.
TEST(ExactGouge, PenetrationAtOnePositionForEachCutter) {
  const PartSolid solid(plate(), 0);
  EXPECT_NEAR(penetration_at(solid, tooling::Cutter::ball(2), {1.5, 10, -0.3}), 0.3, 1e-12);
  EXPECT_NEAR(penetration_at(solid, tooling::Cutter::ball(2), {1.5, 10, 0.25}), -0.25, 1e-12);
  EXPECT_NEAR(penetration_at(solid, tooling::Cutter::flat(4), {12.625, 15, 4.8}), 0.2, 1e-9);
  EXPECT_LE(penetration_at(solid, tooling::Cutter::flat(4), {12.125, 15, 4.8}), 0.0);
  EXPECT_NEAR(penetration_at(solid, tooling::Cutter::bull(4, 1), {1.5, 10, -0.1}), 0.1, 1e-9);
}

namespace {
/// A mushroom seen from above (issue 37 §1's undercut): the plate of 20 × 20 mm at Z −8 (bottom
/// −10) with a stem [8.125, 11.875]² up to Z 0, and a cap [4.125, 15.875]² from Z 0 to Z 2 resting
/// on it, 4 mm over the plate all round: a closed box of its own, so the cap's underside faces down
/// over the plate. A 3-axis machine sees the cap and the column below it as solid.
ingest::Mesh mushroom() {
  const std::vector<double> b{0, 8.125, 11.875, 20};
  ingest::Mesh m = columns(b, b, {{-8, -8, -8}, {-8, 0, -8}, {-8, -8, -8}}, -10);
  const double x0 = 4.125, x1 = 15.875, z0 = 0, z1 = 2;
  const std::array<std::array<double, 3>, 8> c{
      {{x0, x0, z0}, {x1, x0, z0}, {x1, x1, z0}, {x0, x1, z0}, {x0, x0, z1}, {x1, x0, z1}, {x1, x1, z1}, {x0, x1, z1}}};
  // Outward normals: bottom down, top up, the four sides out.
  const std::array<std::array<int, 3>, 12> f{{{0, 2, 1},
                                              {0, 3, 2},
                                              {4, 5, 6},
                                              {4, 6, 7},
                                              {0, 1, 5},
                                              {0, 5, 4},
                                              {1, 2, 6},
                                              {1, 6, 5},
                                              {2, 3, 7},
                                              {2, 7, 6},
                                              {3, 0, 4},
                                              {3, 4, 7}}};
  const Eigen::Index v0 = m.V.rows(), f0 = m.F.rows();
  m.V.conservativeResize(v0 + 8, 3);
  m.F.conservativeResize(f0 + 12, 3);
  for (Eigen::Index i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) m.V(v0 + i, k) = c[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
  for (Eigen::Index i = 0; i < 12; ++i)
    for (int k = 0; k < 3; ++k)
      m.F(f0 + i, k) = static_cast<int>(v0) + f[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
  return m;
}
}  // namespace

// Beside the cap's edge (x = 4.125, on a line of cell centres) down on the plate (tip Z −8), the
// ball's side touching the edge's vertical: the cells on the edge read the cap's top (Z 2) and are
// cut to −7 by the ball's rim, a "gouge" (9 mm vertically, the steep edge's cos makes it 0.22 mm
// along the normal) that the exact check refutes (distance centre–edge = R).
TEST(ExactGouge, BesideAnUndercutCapIsNoGouge) {
  const Checked r = machine_and_check(mushroom(), plunge_and_run(3.125, 5, -8, 3.125, 15), tooling::Cutter::ball(2));
  EXPECT_TRUE(r.zmap.gouged);
  EXPECT_GT(r.zmap.max_gouge_mm, 0.2);
  EXPECT_NEAR(r.zmap.min_e_mm, -9.0, 1e-9);
  EXPECT_TRUE(r.exact.gouge_checked);
  EXPECT_FALSE(r.exact.gouged);
  EXPECT_LE(r.exact.max_gouge_mm, 0.002);
  EXPECT_EQ(r.exact.gouge_places_refuted, r.exact.gouge_places_checked);
}

// Under the cap (x = 5, tip Z −5, between the stem and the cap's edge): reachable only through the
// cap from above, so a real gouge for a 3-axis machine, and both agree on its depth: the ball's
// centre (Z −4) lies 6 mm below the cap's top, penetration R + 6 = 7 mm; the z-map's deepest cells
// under the cap (design Z 2), their centres 0.125 mm off the tool's axis, are cut to
// −5 + f(0.125) = −5 + 1 − √(1 − 0.125²): within one cell's profile of 7 mm.
TEST(ExactGouge, UnderAnUndercutCapTheZMapAndTheExactCheckAgree) {
  const Checked r = machine_and_check(mushroom(), plunge_and_run(5, 6, -5, 5, 14), tooling::Cutter::ball(2));
  ASSERT_TRUE(r.zmap.gouged);
  ASSERT_TRUE(r.exact.gouged);
  EXPECT_NEAR(r.zmap.max_gouge_mm, 7.0 - (1 - std::sqrt(1 - 0.125 * 0.125)), 1e-9);
  EXPECT_NEAR(r.exact.max_gouge_mm, 7.0, 5e-4);
  EXPECT_EQ(r.exact.gouge_places_refuted, 0u);
  EXPECT_NEAR(r.exact.gouge_x_mm, 5, 1e-9);
}

// The nearest approach of swept cutters to points (issue 41's missed rest confirmed), by hand: a
// Ø2 ball along X at tip Z 0 (centre Z 1), a Ø4 bull with 1 mm corners along Y = 20, a Ø2 ball on
// a half circle of radius 5 about (30, 0), and a drill right over the first point (left out).
TEST(ExactGouge, NearestApproachOfTheSweptCuttersByHand) {
  Program ball_line;
  ball_line.items = {mv(Motion::Rapid, 0, 0, 8), mv(Motion::Line, 0, 0, 0), mv(Motion::Line, 10, 0, 0),
                     mv(Motion::Rapid, 10, 0, 8)};
  Program bull_line;
  bull_line.items = {mv(Motion::Rapid, 0, 20, 8), mv(Motion::Line, 0, 20, 0), mv(Motion::Line, 10, 20, 0)};
  Program arc;
  Move half = mv(Motion::ArcCCW, 25, 0, 0);
  half.center = {30, 0};
  arc.items = {mv(Motion::Rapid, 35, 0, 8), mv(Motion::Line, 35, 0, 0), half};
  Program drill;
  drill.items = {mv(Motion::Rapid, 5, 1.5, 8), mv(Motion::Line, 5, 1.5, -3)};
  const std::vector<PassTool> passes{{&ball_line, tooling::Cutter::ball(2)},
                                     {&bull_line, tooling::Cutter::bull(4, 1)},
                                     {&arc, tooling::Cutter::ball(2)},
                                     {&drill, tooling::Cutter::drill(2)}};
  const std::vector<gcode::Point3> points{
      {5, 1.5, 0.2},    // beside the ball: √(1.5² + 0.8²) − 1 = 0.7
      {5, 1.2, 3},      // beside its shank: 1.2 − 1 = 0.2
      {12, 0, 0.5},     // past the line's end, the rapid up: √(2² + 0.5²) − 1
      {5, 23, 0.5},     // beside the bull: √((3 − 1)² + 0.5²) − 1
      {5, 20.5, -0.3},  // under its flat bottom: 0.3
      {30, 6.5, 1},     // outside the arc at the ball centre's height: 6.5 − 5 − 1 = 0.5
      {50, 50, 0},      // near nothing: the reach
      {3, 0, 0.5}};     // inside the ball's sweep: 0
  const std::vector<double> d = nearest_approach(passes, points, 2.0, ExactGougeOptions{});
  ASSERT_EQ(d.size(), points.size());
  const double tol = 1e-3;
  EXPECT_NEAR(d[0], 0.7, tol);
  EXPECT_NEAR(d[1], 0.2, tol);
  EXPECT_NEAR(d[2], std::sqrt(4.25) - 1, tol);
  EXPECT_NEAR(d[3], std::sqrt(4.25) - 1, tol);
  EXPECT_NEAR(d[4], 0.3, tol);
  EXPECT_NEAR(d[5], 0.5, tol);
  EXPECT_EQ(d[6], 2.0);
  EXPECT_EQ(d[7], 0.0);
  // Each point on its own: the same figure asked alone (any order, any thread count).
  for (std::size_t k = 0; k < points.size(); ++k)
    EXPECT_EQ(nearest_approach(passes, {points[k]}, 2.0, ExactGougeOptions{}).front(), d[k]) << k;
  EXPECT_THROW((void)nearest_approach(passes, points, 0.0, ExactGougeOptions{}), millnet::Error);
}
