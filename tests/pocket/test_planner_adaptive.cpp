// The adaptive (constant-engagement) planner: every bench pocket cleared at the issue-11 bench cut
// with no gouge (independent G-code replay), nothing reachable left uncut (independent coverage
// raster), no retraction inside a component, and the feed map's largest engagement of the whole
// program (contour pass included) within the target; a slot narrower than two tool diameters cut
// by curved moves; a lower target; determinism; a tool that fits nowhere.
//
// Engagement tolerance. The metric (max_engagement_deg) reads the feed map's swept width: the area
// each cell of travel newly covers, from the cells' covered shares (pocket/feedmap.cpp), at the
// bench's feed_grid g = 0.25 mm (1/40 D). It reads a straight cut within 0.15 mm (≈ 1.7°; the feed
// map's own test), and the adaptive programs at 90.7–92.5° where the independent 0.05 mm replay
// below (widest_cut) reads 5.02–5.07 mm (90.2–90.8°; 5.03–5.18 mm on the D/40 raster of before
// 2026-11-26): kEngTolDeg = 8° over the target. (Until
// 2026-11-26 it read the count of newly covered cell centres, which strays by several cells a step
// and happened to fall on the planner's own cell centres here: 82.8–84.3°, and 104–108° with the
// planner's raster shifted by half a cell.)
#include "testing/program_text.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <algorithm>
#include <vector>

using namespace millnet::pocket;
using millnet::testing::to_replay;
namespace {

constexpr double kEngTolDeg = 8.0;
// The independent width check (widest_cut): the planner aims at 0.9 of the target's width, and its
// D/80 raster reads a step's crescent a few cells off (≈ ±0.4 mm of width at 0.25 mm steps); the
// 0.05 mm replay itself reads a 0.25 mm piece within ≈ ±0.05 mm. 0.2 mm over 5 mm is ≈ 2.3° over
// 90° (measured: 5.02–5.07 mm; 5.16–5.18 mm with the D/40 raster and 0.85 of before 2026-11-26).
constexpr double kWidthTolMm = 0.2;
// Targets below 90°: the replay's widest cut within this of the target (measured 2026-11-26: 4.2°,
// 1.7°, 1.6° over 45°, 50°, 60°; 6.7°, 7.3°, 6.0° with the D/40 raster).
constexpr double kNarrowTolDeg = 5.0;

CutParams bench_cut() {
  CutParams cut = millnet::testing::issue11_bench_cut();
  cut.feed_grid = 0.25;  // the feed map's engagement at 1/40 D (the default D/10 reads ±10° per cell)
  return cut;
}

struct Outcome {
  PlanResult plan;
  MachiningResult m;
  millnet::testing::ReplayResult rep;
  std::size_t uncovered = 0;  ///< grid points a centred tool could reach that no cutting move swept
  std::size_t probed = 0;
  double turning_rad = 0;  ///< Σ |turn| between consecutive segments of the plan
};

/// As the offset planner's test: plans, machines (helix entry, contour pass), replays the G-code,
/// checks gouges and coverage (every point of a 0.5 mm grid with 0.2 mm to spare for the tool
/// lies within R + 0.01 mm of a replayed cutting move sampled every 0.25 mm).
Outcome run(const Region& region, const CutParams& cut, const AdaptiveParams& ap = {}) {
  Outcome o;
  o.plan = plan(region, cut, AdaptiveSpec{ap});
  for (const Chain& c : o.plan.path.chains)
    for (std::size_t k = 2; k < c.pts.size(); ++k) {
      const Vec2 a = c.pts[k - 1].p() - c.pts[k - 2].p(), b = c.pts[k].p() - c.pts[k - 1].p();
      if (a.norm() > 1e-9 && b.norm() > 1e-9)
        o.turning_rad += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
    }
  MachiningOptions opt;
  opt.entry = Entry::Helix;
  opt.contour = true;
  o.m = machine_pocket(region, cut, o.plan, opt);
  if (const char* dump = std::getenv("ADAPTIVE_DUMP")) {  // debugging aid: the plan's chains as CSV
    if (FILE* f = std::fopen(dump, "w")) {
      for (std::size_t ci = 0; ci < o.m.path.chains.size(); ++ci)
        for (const Vertex& v : o.m.path.chains[ci].pts) std::fprintf(f, "%zu,%.4f,%.4f\n", ci, v.x, v.y);
      std::fclose(f);
    }
  }
  if (o.m.status != PlanStatus::Ok) return o;
  o.rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(o.m.program), cut.safe_z);
  millnet::testing::check_gouge(o.rep, to_replay(region), cut.tool.diameter / 2);
  o.uncovered = millnet::testing::unswept_points(o.rep, region, cut.tool.diameter / 2, o.probed);
  return o;
}

Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }

/// 60 × 40 rectangle with a round island of radius 7.5 at (27.5, 20) (two half-circle bulges).
Region rect_with_round_island() {
  Region r;
  r.boundary = rect(0, 0, 60, 40);
  r.islands = {{{20, 20, -1}, {35, 20, -1}}};
  validate_and_normalize(r, "test");
  return r;
}

/// The tests' own raster of w × hgt mm from the origin, cells of h mm (independent of the planner's).
struct CellGrid {
  double h;
  int nx, ny;
  CellGrid(double w, double hgt, double cell)
      : h(cell), nx(static_cast<int>(w / cell)), ny(static_cast<int>(hgt / cell)) {}
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  [[nodiscard]] Vec2 centre(std::size_t i) const {
    return Vec2((static_cast<double>(i % static_cast<std::size_t>(nx)) + 0.5) * h,
                (static_cast<double>(i / static_cast<std::size_t>(nx)) + 0.5) * h);
  }
  /// Calls f(index) for every cell whose centre lies within rr of c.
  template <class F>
  void disk(const Vec2& c, double rr, F&& f) const {
    const int x0 = std::max(0, static_cast<int>((c.x() - rr) / h)),
              x1 = std::min(nx - 1, static_cast<int>((c.x() + rr) / h));
    const int y0 = std::max(0, static_cast<int>((c.y() - rr) / h)),
              y1 = std::min(ny - 1, static_cast<int>((c.y() + rr) / h));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const auto i = static_cast<std::size_t>(y * nx + x);
        if ((centre(i) - c).squaredNorm() <= rr * rr) f(i);
      }
  }
};

/// The widest cut of the program, measured independently of the planner's raster and the feed
/// map's: the replayed feed moves below the top sampled every g, the cells of a g-grid (material:
/// centre inside the region) cut when their centre comes within R of a sample, and the area newly
/// cut over each `piece` mm of tool path at the floor divided by that length (the new-cut width
/// a_e: 5 mm is 90° on Ø10). Moves above the floor (the helix) cut without being measured. Each
/// sample visits only the cells its disk adds to the previous sample's (O(R·g / g²) per sample).
struct WidthReport {
  double worst_mm = 0;
  Vec2 at{0, 0};                     ///< where the widest piece ends
  std::size_t pieces = 0, over = 0;  ///< pieces measured; pieces wider than `limit`
};
WidthReport widest_cut(const millnet::testing::ReplayResult& rep, const Region& region, double R, double limit,
                       double g = 0.05, double piece = 0.25) {
  WidthReport w;
  const std::vector<Vec2> b = flatten(region.boundary, 0.005);
  std::vector<std::vector<Vec2>> loops{b};
  for (const Loop& l : region.islands) loops.push_back(flatten(l, 0.005));
  Vec2 lo = b.front(), hi = b.front();
  for (const Vec2& p : b) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  lo -= Vec2(R + 1, R + 1);
  hi += Vec2(R + 1, R + 1);
  const int nx = static_cast<int>((hi.x() - lo.x()) / g) + 1, ny = static_cast<int>((hi.y() - lo.y()) / g) + 1;
  std::vector<char> st(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);  // 1 material, 2 cut
  std::vector<double> xs;
  for (int y = 0; y < ny; ++y) {  // even-odd scan lines
    const double yc = lo.y() + (y + 0.5) * g;
    xs.clear();
    for (const auto& l : loops)
      for (std::size_t i = 0; i < l.size(); ++i) {
        const Vec2& a = l[i];
        const Vec2& c = l[(i + 1) % l.size()];
        if ((a.y() <= yc) != (c.y() <= yc)) xs.push_back(a.x() + (yc - a.y()) * (c.x() - a.x()) / (c.y() - a.y()));
      }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
      for (int x = std::max(0, static_cast<int>(std::ceil((xs[k] - lo.x()) / g - 0.5)));
           x <= std::min(nx - 1, static_cast<int>(std::floor((xs[k + 1] - lo.x()) / g - 0.5))); ++x)
        st[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x)] = 1;
  }
  // Cuts the cells within R of c (not within R of prev when has_prev); returns how many were material.
  auto mark = [&](const Vec2& c, const Vec2& prev, bool has_prev) {
    int n = 0;
    const int y0 = std::max(0, static_cast<int>(std::ceil((c.y() - R - lo.y()) / g - 0.5)));
    const int y1 = std::min(ny - 1, static_cast<int>(std::floor((c.y() + R - lo.y()) / g - 0.5)));
    for (int y = y0; y <= y1; ++y) {
      const double yc = lo.y() + (y + 0.5) * g;
      const double w2 = R * R - (yc - c.y()) * (yc - c.y());
      if (w2 < 0) continue;
      const double wr = std::sqrt(w2);
      const int x0 = std::max(0, static_cast<int>(std::ceil((c.x() - wr - lo.x()) / g - 0.5)));
      const int x1 = std::min(nx - 1, static_cast<int>(std::floor((c.x() + wr - lo.x()) / g - 0.5)));
      for (int x = x0; x <= x1; ++x) {
        const double xc = lo.x() + (x + 0.5) * g;
        if (has_prev && (xc - prev.x()) * (xc - prev.x()) + (yc - prev.y()) * (yc - prev.y()) <= R * R) continue;
        char& v = st[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x)];
        if (v == 1) {
          v = 2;
          ++n;
        }
      }
    }
    return n;
  };
  double floor_z = 0;
  for (const auto& mv : rep.moves)
    if (mv.g != 0) floor_z = std::min(floor_z, mv.to[2]);
  Vec2 prev(0, 0);
  bool has_prev = false;
  double run = 0;
  int fresh = 0;
  for (const auto& mv : rep.moves) {
    if (mv.g == 0 || mv.to[2] > -1e-9) {  // rapid or above the top: the disk chain is broken
      has_prev = false;
      run = 0;
      fresh = 0;
      continue;
    }
    const bool at_floor = std::abs(mv.from[2] - floor_z) < 1e-6 && std::abs(mv.to[2] - floor_z) < 1e-6;
    const Vec2 a(mv.from[0], mv.from[1]), e(mv.to[0], mv.to[1]);
    std::function<Vec2(double)> at = [&](double t) { return Vec2(a + t * (e - a)); };
    double len = (e - a).norm();
    if (mv.g != 1) {
      const Vec2 c(mv.center[0], mv.center[1]);
      const double r = (a - c).norm();
      const double a0 = std::atan2(a.y() - c.y(), a.x() - c.x()), a1 = std::atan2(e.y() - c.y(), e.x() - c.x());
      double sweep = a1 - a0;
      if (mv.g == 3 && sweep <= 1e-12) sweep += 2 * M_PI;
      if (mv.g == 2 && sweep >= -1e-12) sweep -= 2 * M_PI;
      len = r * std::abs(sweep);
      at = [c, r, a0, sweep](double t) {
        return Vec2(c + r * Vec2(std::cos(a0 + sweep * t), std::sin(a0 + sweep * t)));
      };
    }
    const int n = std::max(1, static_cast<int>(std::ceil(len / g)));
    for (int k = has_prev ? 1 : 0; k <= n; ++k) {
      const Vec2 q = at(static_cast<double>(k) / n);
      const int got = mark(q, prev, has_prev);
      if (at_floor && has_prev) {
        fresh += got;
        run += len / n;
        if (run >= piece - 1e-9) {
          const double width = fresh * g * g / run;
          ++w.pieces;
          if (width > limit) ++w.over;
          if (width > w.worst_mm) {
            w.worst_mm = width;
            w.at = q;
          }
          run = 0;
          fresh = 0;
        }
      }
      prev = q;
      has_prev = true;
    }
    if (!at_floor) {
      run = 0;
      fresh = 0;
    }
  }
  return w;
}

std::size_t components(const Region& r, const CutParams& cut) {
  return offset_inward(r, cut.clearance() + 0.001).size();
}

}  // namespace

class AdaptiveBench : public ::testing::TestWithParam<const char*> {};

TEST_P(AdaptiveBench, ClearsAtTheTargetEngagementWithNoGouge) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + GetParam() + ".json");
  const CutParams cut = bench_cut();
  const Outcome o = run(pf.region, cut);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_EQ(o.plan.planner, "adaptive");
  EXPECT_TRUE(o.plan.walls_cut);
  const auto& st = std::get<AdaptiveStats>(o.plan.stats);
  EXPECT_NEAR(st.target_deg, 90.0, 1e-9);  // stepover 5 on Ø10
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_LT(o.rep.worst_mm, 0.01);
  const std::size_t comps = components(pf.region, cut);
  EXPECT_LE(o.m.metrics.retractions, static_cast<double>(comps) - 1);
  EXPECT_LE(o.rep.retractions, static_cast<int>(comps) - 1);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_GT(o.probed, 1000u);
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.max_engagement_deg, st.target_deg + kEngTolDeg);
  // The feed map's grid and the planner's raster share their cell centres on these pockets (both
  // D/40 from the outline's box). A replay on a grid of its own, 0.05 mm, of the program: at most
  // the target width a_e = 5 mm plus kWidthTolMm.
  const WidthReport wr = widest_cut(o.rep, pf.region, cut.tool.diameter / 2, 5.0);
  std::printf("[ adaptive ] %s: widest cut %.3f mm at (%.3f, %.3f), %zu of %zu pieces over 5 mm\n", GetParam(),
              wr.worst_mm, wr.at.x(), wr.at.y(), wr.over, wr.pieces);
  EXPECT_GT(wr.pieces, 10000u);
  EXPECT_LE(wr.worst_mm, 5.0 + kWidthTolMm) << "at " << wr.at.transpose();
  EXPECT_LE(wr.over * 1000, wr.pieces);  // a few pieces a thousand above 5 mm, none far above
  // Few passes that cut nothing (each costs a stop and a start): where no pass can start at the
  // end of a ride back, the ride and the link beyond it are one move. Before: 96 of 257, 81 of
  // 174, 144 of 334 passes; then 18 / 180, 5 / 98, 11 / 197 on the D/40 raster; 21 / 166,
  // 0 / 98, 17 / 202 on the D/80 raster (a pass "cuts nothing" below 1 mm², the 4 D/40 cells).
  EXPECT_LE(st.idle_passes * 6, st.passes) << st.idle_passes << " of " << st.passes;
  // The figures the report quotes (no timing assertion).
  std::printf(
      "[ adaptive ] %s: time_kinematic_min %.3f uncut %.3f mm2 retractions %.0f max_engagement %.1f deg "
      "planning %.3f s cut %.0f mm vertices %zu passes %zu links %zu reentries %zu wall_retractions %zu\n",
      GetParam(), o.m.metrics.time_kinematic_min, o.m.metrics.uncut_area_mm2, o.m.metrics.retractions,
      o.m.metrics.max_engagement_deg, o.plan.planning_time_s, o.m.metrics.cut_length_mm, st.vertices, st.passes,
      st.links, st.reentries, st.wall_retractions);
}

INSTANTIATE_TEST_SUITE_P(Pockets, AdaptiveBench, ::testing::Values("four_islands", "comb", "eight_islands"));

TEST(PlannerAdaptive, ASlotNarrowerThanTwoDiametersIsCutByCurvedMoves) {
  // 16 mm wide: a straight pass down the middle would slot at 180°; the tool centre has a 6 mm
  // strip, so the planner must loop (trochoidal moves) to keep 90°.
  Region r;
  r.boundary = rect(0, 0, 100, 16);
  validate_and_normalize(r, "test");
  const CutParams cut = bench_cut();
  const Outcome o = run(r, cut);
  ASSERT_EQ(o.m.status, PlanStatus::Ok) << o.m.message;
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.m.metrics.retractions, 0);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.max_engagement_deg, 90 + kEngTolDeg);
  // The centres' strip is 90 mm long: curved moves make the path far longer and turn many times.
  EXPECT_GT(o.plan.path.cut_length(), 2.5 * 90);
  EXPECT_GT(o.turning_rad, 10 * 2 * M_PI);
}

TEST(PlannerAdaptive, ALowerTargetCutsLongerAndEngagesLess) {
  const Region r = rect_with_round_island();
  const CutParams cut = bench_cut();
  AdaptiveParams a90, a45;
  a45.max_engagement_deg = 45;
  const Outcome o90 = run(r, cut, a90), o45 = run(r, cut, a45);
  ASSERT_EQ(o90.m.status, PlanStatus::Ok);
  ASSERT_EQ(o45.m.status, PlanStatus::Ok);
  EXPECT_EQ(o45.rep.violations, 0) << o45.rep.first_violation;
  EXPECT_EQ(o45.uncovered, 0u);
  EXPECT_LE(o45.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_GT(o45.plan.path.cut_length(), 1.3 * o90.plan.path.cut_length());
  EXPECT_LT(o45.m.metrics.max_engagement_deg, o90.m.metrics.max_engagement_deg);
  EXPECT_LE(o90.m.metrics.max_engagement_deg, 90 + kEngTolDeg);
}

// The rides back along a front are pulled taut (2026-11-25): a ride of 0.25 mm steps turning a
// few degrees each held the machine to ≈ 36 mm/s by the junction-deviation rule where its air
// feed allows 80. Independent oracle: the plan's moves replayed in order on a 0.25 mm raster (a
// cell inside the region is cut when its centre lies within R of a sample every 0.25 mm); a move
// that cuts ≤ 3 cells is in the air. "Stepping": an air move that ends a run of ≥ 4 air moves,
// each ≤ 1.5 steps long, away from the walls (the wall loops follow the island's arcs in short
// chords). "Superfluous": a vertex between two air moves a→b→c where the straight a→c keeps
// 0.3 mm more than the clearance from the walls and has no uncut cell within R + 0.3 mm.
TEST(PlannerAdaptive, RidesCutNothingAndArePulledTaut) {
  const Region r = rect_with_round_island();
  const CutParams cut = bench_cut();
  const PlanResult p = plan(r, cut, AdaptiveSpec{});
  ASSERT_EQ(p.status, PlanStatus::Ok);
  const double R = cut.tool.diameter / 2, h = 0.25;
  const CellGrid grid(60, 40, h);
  std::vector<char> cut_cells(grid.size(), 0);
  const auto disk = [&](const Vec2& c, double rr, auto&& f) { grid.disk(c, rr, f); };
  const auto samples = [&](const Vec2& a, const Vec2& b) {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / h)));
    std::vector<Vec2> out;
    for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (static_cast<double>(i) / n));
    return out;
  };
  const Clearance spare(r, cut.clearance() + 0.3);
  std::size_t air_vertices = 0, superfluous = 0, air_moves = 0, moves = 0;
  double air_mm = 0;
  std::size_t stepping = 0;  // air moves that end a run of ≥ 4 step-long air moves
  for (const Chain& c : p.path.chains) {
    ASSERT_FALSE(c.pts.empty());
    disk(c.pts.front().p(), R, [&](std::size_t i) { cut_cells[i] = 1; });
    bool prev_air = false;
    int step_run = 0;
    for (std::size_t k = 1; k < c.pts.size(); ++k) {
      const Vec2 a = c.pts[k - 1].p(), b = c.pts[k].p();
      int fresh = 0;
      for (const Vec2& q : samples(a, b))
        disk(q, R, [&](std::size_t i) {
          const Vec2 cc = grid.centre(i);
          if (!cut_cells[i] && inside(r, cc)) ++fresh;
          cut_cells[i] = 1;
        });
      const bool air = fresh <= 3;
      ++moves;
      air_moves += air;
      if (air) air_mm += (b - a).norm();
      // A ride of steps: four air moves in a row, each no longer than a step and a half, away
      // from the walls (the wall loops' vertices follow the islands' arcs closely).
      step_run = (air && (b - a).norm() <= 1.5 * h && spare.point_ok(a) && spare.point_ok(b)) ? step_run + 1 : 0;
      stepping += step_run >= 4;
      if (air && prev_air && k >= 2) {
        ++air_vertices;
        const Vec2 a0 = c.pts[k - 2].p();
        bool clear = spare.move_ok(a0, b);
        for (const Vec2& q : samples(a0, b)) {
          if (!clear) break;
          disk(q, R + 0.3, [&](std::size_t i) {
            const Vec2 cc = grid.centre(i);
            if (!cut_cells[i] && inside(r, cc)) clear = false;
          });
        }
        superfluous += clear;
      }
      prev_air = air;
    }
  }
  std::printf("moves %zu, in the air %zu (%.1f mm), air vertices %zu, superfluous %zu, stepping %zu\n", moves,
              air_moves, air_mm, air_vertices, superfluous, stepping);
  EXPECT_GT(air_moves, 20u);  // the rides and links exist
  // Rides of steps: 227 of 1,869 air moves before the change, 16 of 697 after.
  EXPECT_LE(stepping, air_moves / 20);
  // A vertex of the air that a straight move with room to spare could skip: 13 of 642 (the taut
  // pull goes from the ride's own points; links pulled taut by link_ok may cut up to the target).
  EXPECT_LE(superfluous, air_vertices / 20 + 2);
}

// Targets below 90° on a rectangle with a round island. Until 2026-11-25 the 45° case read 53–60°
// (75.5° before the passes sensed the material beyond one step), and 50° / 60° read 77.0° / 79.9°:
// the passes left the wall pass a sliver about one raster cell thick along every wall, and where
// the wall pass turns a corner of the rectangle it takes a quarter arc of it in under a millimetre
// of travel (located at the four corners; fillet passes and spring loops were tried and made it
// worse). Below 85° the passes now take that band themselves (adaptive_prepare.cpp, mark_target()).
// Those figures were centre counts on a grid that shares the planner's cell centres; the swept
// width (2026-11-26) reads 56.1° / 60.6° / 68.1°, the independent replay 51.7° / 57.3° / 66.0°: the
// planner's raster noise (±2–3 cells a step, 0.66–0.85 mm of width over what it aims at) weighs
// more at a narrow target. On the D/80 raster (2026-11-26) the replay reads 49.2° / 51.7° / 61.6°
// and the swept width 49.4° / 53.4° / 62.9°; a pass is worth starting below the 4 D/40 cells there
// (every corner remnant must be taken by a pass, not the wall pass).
class AdaptiveTarget : public ::testing::TestWithParam<double> {};

TEST_P(AdaptiveTarget, StaysWithinItsToleranceAtTheCornersToo) {
  const Region r = rect_with_round_island();
  AdaptiveParams a;
  a.max_engagement_deg = GetParam();
  const Outcome o = run(r, bench_cut(), a);
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  // The metric reads widths within ≈ 0.15 mm (the feed map's test); at these narrow cuts a width
  // error weighs more in degrees (dθ = dw / (R sin θ): 0.25 mm is 4.1° at 45°, 2.9° at 90°).
  const double R = bench_cut().tool.diameter / 2, th = GetParam() * M_PI / 180;
  EXPECT_LE(o.m.metrics.max_engagement_deg, GetParam() + kNarrowTolDeg + 0.25 / (R * std::sin(th)) * 180 / M_PI);
  // The independent replay: within kNarrowTolDeg of the target (measured: 49.2°, 51.7°, 61.6°).
  const WidthReport wr = widest_cut(o.rep, r, R, R * (1 - std::cos(th)));
  std::printf(
      "[ adaptive ] target %.0f deg: widest cut %.3f mm (%.1f deg) at (%.2f, %.2f), metric %.1f deg, %.3f min\n",
      GetParam(), wr.worst_mm, std::acos(1 - wr.worst_mm / R) * 180 / M_PI, wr.at.x(), wr.at.y(),
      o.m.metrics.max_engagement_deg, o.m.metrics.time_kinematic_min);
  EXPECT_LE(wr.worst_mm, R * (1 - std::cos(th + kNarrowTolDeg * M_PI / 180))) << "at " << wr.at.transpose();
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.uncut_area_mm2, 2.0);
}

INSTANTIATE_TEST_SUITE_P(BelowNinety, AdaptiveTarget, ::testing::Values(45.0, 50.0, 60.0));

TEST(PlannerAdaptive, ConventionalMillingAlsoKeepsTheTarget) {
  Region r;
  r.boundary = rect(0, 0, 50, 40);
  validate_and_normalize(r, "test");
  AdaptiveParams conv;
  conv.climb = false;
  const Outcome o = run(r, bench_cut(), conv);
  ASSERT_EQ(o.m.status, PlanStatus::Ok);
  EXPECT_EQ(o.rep.violations, 0) << o.rep.first_violation;
  EXPECT_EQ(o.uncovered, 0u);
  EXPECT_LE(o.m.metrics.max_engagement_deg, 90 + kEngTolDeg);
}

/// An independent raster replay of a plan's chains (cells of 0.25 mm inside the region): for
/// every move, the fresh cells it cuts and on which side of the move they lie. Climb milling with
/// M3 keeps the material on the right of the direction of travel.
struct Sides {
  double right_mm = 0, left_mm = 0, air_mm = 0;
};
Sides material_sides(const Region& r, const PlanResult& p, double R, double w, double hgt) {
  const double h = 0.25;
  const CellGrid grid(w, hgt, h);
  std::vector<char> cut_cells(grid.size(), 0);
  Sides s;
  // Marks the disk at c; adds the fresh cells' offsets from `from` to acc (count in n).
  const auto mark = [&](const Vec2& c, const Vec2& from, Vec2& acc, int& n) {
    grid.disk(c, R, [&](std::size_t i) {
      if (cut_cells[i]) return;
      cut_cells[i] = 1;
      const Vec2 cc = grid.centre(i);
      if (!inside(r, cc)) return;
      acc += cc - from;
      ++n;
    });
  };
  for (const Chain& c : p.path.chains) {
    Vec2 acc(0, 0);
    int n = 0;
    mark(c.pts.front().p(), c.pts.front().p(), acc, n);
    for (std::size_t k = 1; k < c.pts.size(); ++k) {
      const Vec2 a = c.pts[k - 1].p(), b = c.pts[k].p();
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / h)));
      acc = Vec2(0, 0);
      n = 0;
      for (int i = 1; i <= steps; ++i) mark(a + (b - a) * (static_cast<double>(i) / steps), a, acc, n);
      const double len = (b - a).norm();
      if (n <= 3 || len < 1e-9) {
        s.air_mm += len;
        continue;
      }
      const Vec2 d = (b - a) / len;
      (d.x() * acc.y() - d.y() * acc.x() > 0 ? s.left_mm : s.right_mm) += len;
    }
  }
  return s;
}

TEST(PlannerAdaptive, BothWaysTurnsAtTheWallsInsteadOfRidingBack) {
  // direction "both": a pass a wall stops turns round and cuts the next stripe back conventionally
  // (the material on its left) instead of riding back through the air to climb-cut it. Against
  // the climb-only plan of the same pocket: a large share of the cutting with the material on the
  // left (climb-only: almost none), less air, and the same guarantees (target, no gouge, cleared).
  const Region r = rect_with_round_island();
  const CutParams cut = bench_cut();
  const double R = cut.tool.diameter / 2;
  AdaptiveParams both;
  both.both_ways = true;
  const Outcome ob = run(r, cut, both), oc = run(r, cut);
  ASSERT_EQ(ob.m.status, PlanStatus::Ok);
  ASSERT_EQ(oc.m.status, PlanStatus::Ok);
  const Sides sb = material_sides(r, ob.plan, R, 60, 40), sc = material_sides(r, oc.plan, R, 60, 40);
  std::printf("climb: right %.0f left %.0f air %.0f mm, %.3f min; both: right %.0f left %.0f air %.0f mm, %.3f min\n",
              sc.right_mm, sc.left_mm, sc.air_mm, oc.m.metrics.time_kinematic_min, sb.right_mm, sb.left_mm, sb.air_mm,
              ob.m.metrics.time_kinematic_min);
  EXPECT_LE(sc.left_mm, 0.05 * (sc.left_mm + sc.right_mm));
  EXPECT_GE(sb.left_mm, 0.2 * (sb.left_mm + sb.right_mm));
  EXPECT_LE(sb.air_mm, 0.9 * sc.air_mm);
  EXPECT_EQ(ob.rep.violations, 0) << ob.rep.first_violation;
  EXPECT_EQ(ob.uncovered, 0u);
  EXPECT_LE(ob.m.metrics.uncut_area_mm2, 2.0);
  EXPECT_LE(ob.m.metrics.max_engagement_deg, 90 + kEngTolDeg);
  EXPECT_EQ(ob.m.metrics.retractions, 0);
}

TEST(PlannerAdaptive, SameInputSameProgram) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/four_islands.json");
  const CutParams cut = bench_cut();
  MachiningOptions opt;
  opt.entry = Entry::Helix;
  opt.contour = true;
  const std::string a = millnet::testing::linuxcnc_text(
      machine_pocket(pf.region, cut, plan(pf.region, cut, AdaptiveSpec{}), opt).program);
  const std::string b = millnet::testing::linuxcnc_text(
      machine_pocket(pf.region, cut, plan(pf.region, cut, AdaptiveSpec{}), opt).program);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

TEST(PlannerAdaptive, AToolThatFitsNowhereIsAStatus) {
  Region r;
  r.boundary = rect(0, 0, 40, 8);  // narrower than the Ø10 tool
  validate_and_normalize(r, "test");
  const PlanResult p = plan(r, bench_cut(), AdaptiveSpec{});
  EXPECT_EQ(p.status, PlanStatus::NoToolPoints);
  EXPECT_TRUE(p.path.chains.empty());
  EXPECT_FALSE(p.message.empty());
  EXPECT_EQ(planner_name(AdaptiveSpec{}), "adaptive");
}

TEST(PlannerAdaptive, BadParametersThrow) {
  Region r;
  r.boundary = rect(0, 0, 40, 40);
  validate_and_normalize(r, "test");
  AdaptiveParams a;
  a.max_engagement_deg = 200;
  EXPECT_THROW((void)plan_adaptive(r, bench_cut(), a), millnet::Error);
  AdaptiveParams s;
  s.safety = 0;
  EXPECT_THROW((void)plan_adaptive(r, bench_cut(), s), millnet::Error);
  EXPECT_NEAR(adaptive_target_deg(bench_cut(), AdaptiveParams{}), 90.0, 1e-9);
}

TEST(PocketFeedMap, AnEntryHoleIsClearedBeforeTheChainStarts) {
  // A straight 20 mm move from a plunge point slots (180°); with the helix's disk (radius 9)
  // marked first, the move inside it cuts nothing until it leaves the disk.
  Region r;
  r.boundary = rect(0, 0, 60, 60);
  validate_and_normalize(r, "test");
  CutParams cut = bench_cut();
  auto first_engagement = [&](const std::vector<EntryHole>& holes) {
    Path2D p;
    Chain c;
    c.pts = {{30, 30, 0}, {32, 30, 0}};
    p.chains.push_back(c);
    return assign_feeds(p, r, cut, 5, holes).pieces.front().engagement;
  };
  EXPECT_GT(first_engagement({}), 30);  // ≈ n1 = 40 cells: a slot
  EXPECT_EQ(first_engagement({EntryHole{0, {30, 30}, 9.0}}), 0.0);
}
