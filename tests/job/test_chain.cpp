// The chain of programs on one stock (job/chain.hpp), issue 41's figures: the share of the feed
// path that cuts air (by hand on a plate) and the rest-machining scoring of a last, smaller tool.
#include "millnet/job/chain.hpp"
#include "millnet/core/error.hpp"
#include "millnet/job/frame.hpp"

#include "ingest/builders.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

namespace millnet::job {
namespace {

using gcode::Motion;
using tooling::Cutter;

gcode::Move to(Motion m, double x, double y, double z, double feed = 0) {
  gcode::Move mv;
  mv.motion = m;
  mv.to = {x, y, z};
  mv.feed = feed;
  return mv;
}

// A 20 × 20 plate 5 high; stock top 1 above it, so its top is at program Z −1 and the finishing
// stock (allowance 0.1) at −0.9, on 0.05 mm cells. The program plunges at X5 (6 mm, cuts 0.1 at its
// foot), cuts to X15 along Z −1 (10 mm), rapids up to Z 0 and feeds back to X5 above the stock
// (10 mm of air).
struct Plate {
  ingest::Mesh mesh = testing_ingest::box(0, 0, 0, 20, 20, 5);
  Frame frame = frame_of(mesh, 1.0);
  SimParams sim = [] {
    SimParams s;
    s.cell_mm = 0.05;
    return s;
  }();
  Design design = design_surface(mesh, frame, sim);
  gcode::Program program = [] {
    gcode::Program p;
    p.items = {to(Motion::Rapid, 5, 10, 5), to(Motion::Line, 5, 10, -1, 300), to(Motion::Line, 15, 10, -1, 300),
               to(Motion::Rapid, 15, 10, 0), to(Motion::Line, 5, 10, 0, 300)};
    return p;
  }();
  [[nodiscard]] simulate::ZMap stock() const { return finishing_stock(design, frame, sim); }
};

// The plate's program: air 10 of 26 mm of feed.
TEST(JobChain, AirCutShareIsTheFeedLengthThatRemovesNothing) {
  const Plate c;
  const Design& design = c.design;
  const Frame& frame = c.frame;
  const SimParams& sim = c.sim;
  const gcode::Program& p = c.program;
  simulate::ZMap stock = c.stock();
  const std::vector<ChainStep> steps{{&p, Cutter::ball(2)}};
  const std::vector<StepResult> r = machine_steps(stock, design, steps, gcode::MotionModel{});
  ASSERT_EQ(r.size(), 1U);
  EXPECT_NEAR(r[0].feed_mm, 26, 1e-9);
  EXPECT_NEAR(r[0].air_feed_mm, 10, 1e-9);
  EXPECT_NEAR(r[0].air_cut_share(), 10.0 / 26, 1e-9);
  EXPECT_EQ(r[0].outside_feed_mm, 0.0);
  EXPECT_NEAR(r[0].air_run_feed_mm, 10, 1e-9);  // one run of 10 mm: longer than the Ø2 ball

  // Feed moves whose cutter never reaches the z-map (the grid is the plate's 20 × 20 footprint),
  // like a roughing's passes round the part in the stock's margin: 8 mm at Y −3 (the Ø2 ball's band
  // reaches Y −2 < 0) and a half circle of radius 2 round (−5, 10) (its band reaches X −2): not
  // measured, so neither cut nor air; a 4 mm pass at Y −0.5 that grazes the grid's edge counts.
  simulate::ZMap stock2 = finishing_stock(design, frame, sim);
  gcode::Program q = p;
  gcode::Move arc = to(Motion::ArcCCW, -5, 12, 0, 300);
  arc.center = {-5, 10};
  q.items.insert(q.items.end(),
                 {to(Motion::Rapid, 2, -3, 0), to(Motion::Line, 10, -3, 0, 300), to(Motion::Rapid, -5, 8, 0), arc,
                  to(Motion::Rapid, 2, -0.5, 0), to(Motion::Line, 6, -0.5, 0, 300)});
  const std::vector<StepResult> r2 = machine_steps(stock2, design, {{&q, Cutter::ball(2)}}, gcode::MotionModel{});
  EXPECT_NEAR(r2[0].outside_feed_mm, 8 + 2 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(r2[0].feed_mm, 26 + 4, 1e-9);
  EXPECT_NEAR(r2[0].air_feed_mm, 10 + 4, 1e-9);  // the grazing pass above the plate's top cuts nothing
  EXPECT_NEAR(r2[0].air_run_feed_mm, 10 + 4, 1e-9);

  // A gap bridged along a pass: cut X5 → X15 at Z −1, back 1 mm over what it cut (air), on to X18
  // (cuts X16..X19 again): 1 mm of air, but no run longer than the ball's 2 mm diameter.
  simulate::ZMap stock3 = finishing_stock(design, frame, sim);
  gcode::Program b;
  b.items = {to(Motion::Rapid, 5, 10, 5), to(Motion::Line, 5, 10, -1, 300), to(Motion::Line, 15, 10, -1, 300),
             to(Motion::Line, 14, 10, -1, 300), to(Motion::Line, 18, 10, -1, 300)};
  const std::vector<StepResult> r3 = machine_steps(stock3, design, {{&b, Cutter::ball(2)}}, gcode::MotionModel{});
  EXPECT_NEAR(r3[0].air_feed_mm, 1, 1e-9);
  EXPECT_EQ(r3[0].air_run_feed_mm, 0.0);
  EXPECT_NEAR(r3[0].air_run_share(), 0.0, 1e-15);
}

// Asked for, every move is recorded with what it cut: the plate's program by hand — a rapid, the
// plunge (cuts the 0.1 mm allowance at its foot), the 10 mm cut, the rapid up and the 10 mm of air —
// and written as CSV in the program's own frame (XY less the work origin).
TEST(JobChain, EveryMoveIsRecordedWithWhatItCutAndTheAirRowsSumToTheAirFeed) {
  const Plate c;
  const Design& design = c.design;
  const Frame& frame = c.frame;
  const SimParams& sim = c.sim;
  const gcode::Program& p = c.program;
  simulate::ZMap stock = c.stock();
  const std::vector<StepResult> r = machine_steps(stock, design, {{&p, Cutter::ball(2)}}, gcode::MotionModel{}, true);
  ASSERT_EQ(r.size(), 1U);
  const std::vector<MoveRecord>& m = r[0].moves;
  ASSERT_EQ(m.size(), 5U);
  using K = MoveRecord::Kind;
  const std::array<K, 5> kinds{K::Rapid, K::Cut, K::Cut, K::Rapid, K::Air};
  const std::array<double, 5> lengths{0, 6, 10, 1, 10};
  double air = 0;
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(m[i].item, i);
    EXPECT_EQ(m[i].kind, kinds[i]) << i;
    EXPECT_NEAR(m[i].length_mm, lengths[i], 1e-12) << i;
    if (m[i].kind == K::Air) air += m[i].length_mm;
  }
  // The allowance, as the cells' centres see it: the nearest lie 0.025 mm off the tip in X and Y
  // (the plunge at X5 Y10) or in Y (along the cut), where the Ø2 ball stands 1 − √(1 − d²) higher.
  EXPECT_NEAR(m[1].cut_mm, 0.1 - (1 - std::sqrt(1 - 2 * 0.025 * 0.025)), 1e-9);
  EXPECT_NEAR(m[2].cut_mm, 0.1 - (1 - std::sqrt(1 - 0.025 * 0.025)), 1e-9);
  EXPECT_EQ(m[4].cut_mm, 0.0);
  EXPECT_EQ(air, r[0].air_feed_mm);
  // Not asked: nothing recorded, the same figures.
  simulate::ZMap again = finishing_stock(design, frame, sim);
  const std::vector<StepResult> plain = machine_steps(again, design, {{&p, Cutter::ball(2)}}, gcode::MotionModel{});
  EXPECT_TRUE(plain[0].moves.empty());
  EXPECT_EQ(plain[0].air_feed_mm, r[0].air_feed_mm);
  EXPECT_EQ(plain[0].feed_mm, r[0].feed_mm);
  // As CSV, in the program's frame (work origin at X2 Y3 of millnet's).
  const std::string csv = moves_csv(r, {"plate.nc"}, {2, 3});
  std::vector<std::string> rows;
  for (std::size_t at = 0, nl; (nl = csv.find('\n', at)) != std::string::npos; at = nl + 1)
    rows.push_back(csv.substr(at, nl - at));
  ASSERT_EQ(rows.size(), 6U) << csv;
  EXPECT_EQ(rows[0], "program,line,motion,x,y,z,length_mm,cut_mm,kind");
  EXPECT_EQ(rows[1], "plate.nc,0,G0,3.0000,7.0000,5.0000,0.000000,0.000000,rapid");
  EXPECT_EQ(rows[2], "plate.nc,0,G1,3.0000,7.0000,-1.0000,6.000000,0.099375,cut");
  EXPECT_EQ(rows[3], "plate.nc,0,G1,13.0000,7.0000,-1.0000,10.000000,0.099687,cut");
  EXPECT_EQ(rows[4], "plate.nc,0,G0,13.0000,7.0000,0.0000,1.000000,0.000000,rapid");
  EXPECT_EQ(rows[5], "plate.nc,0,G1,3.0000,7.0000,0.0000,10.000000,0.000000,air");
  // A feed move of no length where the tool stands (it lowers nothing) is air of 0 mm, not a cut.
  gcode::Program still = p;
  const gcode::Move& last = std::get<gcode::Move>(p.items.back());
  still.items.push_back(to(Motion::Line, last.to[0], last.to[1], last.to[2], 300));
  simulate::ZMap third = finishing_stock(design, frame, sim);
  const std::vector<StepResult> r4 =
      machine_steps(third, design, {{&still, Cutter::ball(2)}}, gcode::MotionModel{}, true);
  ASSERT_EQ(r4[0].moves.size(), 6U);
  EXPECT_EQ(r4[0].moves.back().kind, K::Air);
  EXPECT_EQ(r4[0].moves.back().length_mm, 0.0);
  EXPECT_EQ(r4[0].air_feed_mm, r[0].air_feed_mm);
  EXPECT_EQ(r4[0].feed_mm, r[0].feed_mm);
}

// Asked for, a last program with a smaller tool than a finishing one before it is rest machining,
// scored with that reference too; a larger last tool, a flat end mill before (roughing) or a
// chain not asked is not (`millnet run`'s rough + finish chain pays no rest tests).
TEST(JobChain, ASmallerLastToolIsScoredAsRestMachiningBehindTheOneBefore) {
  const ingest::Mesh plate = testing_ingest::box(0, 0, 0, 20, 20, 5);
  const Frame frame = frame_of(plate, 1.0);
  SimParams sim;
  sim.cell_mm = 0.1;
  const Design design = design_surface(plate, frame, sim);
  gcode::Program p;
  p.items = {to(Motion::Rapid, 10, 10, 5)};
  {
    simulate::ZMap stock = finishing_stock(design, frame, sim);
    const ChainResult r =
        machine_chain(stock, design, {{&p, Cutter::ball(6)}, {&p, Cutter::ball(2)}}, gcode::MotionModel{}, sim, true);
    EXPECT_TRUE(r.rest_step);
    EXPECT_EQ(r.rest_reference.describe(), Cutter::ball(6).describe());
    EXPECT_EQ(r.steps.size(), 2U);
    EXPECT_EQ(r.rest_area_before_mm2, r.rest_area_after_mm2);  // the rapid above removes nothing
  }
  for (const auto& [a, b, score] : {std::tuple{Cutter::ball(2), Cutter::ball(6), true},      // a larger last tool
                                    std::tuple{Cutter::flat(10), Cutter::ball(2), true},     // roughing, finishing
                                    std::tuple{Cutter::ball(6), Cutter::ball(2), false}}) {  // not asked
    simulate::ZMap stock = finishing_stock(design, frame, sim);
    const ChainResult r = machine_chain(stock, design, {{&p, a}, {&p, b}}, gcode::MotionModel{}, sim, score);
    EXPECT_FALSE(r.rest_step) << a.describe() << " then " << b.describe();
    EXPECT_EQ(r.steps.size(), 2U);
  }
}

// A wall that steepens from 45° to 80° at x = c = 5.05 (a concave kink turning 35°). A Ø1 ball
// resting in it touches both faces R·tan 17.5° = 0.158 mm from the kink and stays off the design
// by more than the 0.02 mm threshold only within s < 0.158 − √(0.52² − 0.5²) = 0.0149 mm of it
// along each face: an XY band from c − 0.0105 (the 45° face) to c + 0.0026 (the 80° face),
// narrower than the rest test's 0.1 mm nodes (5.0 and 5.1, both outside it). Under a stock 0.1 mm
// over the design (0.071 along the 45° face's normal: rest; 0.017 on the 80° face: not) behind a
// Ø10 reference, the cells in that band are rest the Ø1 cannot reach, never missed rest; those on
// the 45° face clear of it are missed. (By the nearest node alone both were missed.)
TEST(JobChain, RestInABandNarrowerThanTheReachTestsNodesIsSplitByTheExactTest) {
  const double c = 5.05, a = std::tan(80 * std::numbers::pi / 180);
  const ingest::Mesh wall =
      testing_ingest::solid([&](double x, double) { return x <= c ? x : c + a * (x - c); }, 0, 6.5, 0, 6, 130, 1, -1);
  const Frame frame = frame_of(wall, 0.5);
  SimParams sim;
  sim.cell_mm = 0.005;
  const Design design = design_surface(wall, frame, sim);
  const simulate::ZMap stock = finishing_stock(design, frame, sim);  // the design + 0.1
  ChainResult r;
  r.rest_step = true;
  r.rest_reference = Cutter::ball(10);
  r.rest_above_before = simulate::cells_above(stock, design.heights, sim.rest_threshold_mm);
  const RestSplit split = split_rest(wall, design, stock, r, {}, Cutter::ball(1), sim.rest_threshold_mm,
                                     -std::numeric_limits<double>::infinity(), frame.z_shift());
  const simulate::GridSpec& g = design.grid;
  int band = 0, clear = 0;
  for (std::size_t i = 0; i < g.cells(); ++i) {
    const double x = g.x(i % g.nx), y = g.y(i / g.nx);
    if (y < 2.5 || y > 3.5) continue;  // away from the ends, where the tools come in from the side
    const double s = x <= c ? (c - x) * std::numbers::sqrt2 : (x - c) / std::cos(80 * std::numbers::pi / 180);
    if (s < 0.0149 - 0.001) {
      ++band;
      EXPECT_TRUE(std::isnan(split.missed[i])) << "x " << x << " y " << y << ": the Ø1 cannot reach it";
    } else if (x < c - 0.0105 - 0.01 && x > c - 0.4) {
      ++clear;
      EXPECT_FALSE(std::isnan(split.missed[i])) << "x " << x << " y " << y << ": the Ø1 reaches it";
    }
  }
  EXPECT_GE(band, 2 * 200);  // two cells a row (x 5.0425 and 5.0475), 200 rows
  EXPECT_GT(clear, 70 * 200);
  EXPECT_GT(split.missed_mm2, 0.0);
  EXPECT_EQ(split.missed_zmap_mm2, split.missed_mm2);  // no program to confirm it by: the z-map's word

  // A Ø1 program that touched the 45° face along Y 2.4 … 3.6 at X c − 0.45 … c − 0.115 (contacts
  // 0.02 mm apart, the bitangent's 0.112 the closest it may come): it came within 0.001 mm of every
  // cell of that face up to c − 0.014, so the z-map's excess there (a stock handed over, never cut
  // by it) is no missed rest; beside the program (Y 4.5 … 5.5) the missed cells stay.
  gcode::Program touch;
  const double R = 0.5;
  for (int k = 0; k <= 17; ++k) {
    const double xc = std::min(c - 0.45 + 0.02 * k, c - 0.115);
    const double cx = xc - R / std::numbers::sqrt2, tip = xc + R / std::numbers::sqrt2 - R + frame.z_shift();
    for (const double y : {2.4, 3.6}) {
      gcode::Move m;
      m.motion = Motion::Line, m.to = {cx, y, tip}, m.feed = 600;
      touch.items.emplace_back(m);
    }
  }
  const RestSplit confirmed =
      split_rest(wall, design, stock, r, {{&touch, Cutter::ball(1)}}, Cutter::ball(1), sim.rest_threshold_mm,
                 -std::numeric_limits<double>::infinity(), frame.z_shift());
  int beside = 0;
  for (std::size_t i = 0; i < g.cells(); ++i) {
    const double x = g.x(i % g.nx), y = g.y(i / g.nx);
    if (!(x < c - 0.0105 - 0.01 && x > c - 0.4)) continue;
    if (y > 2.5 && y < 3.5) EXPECT_TRUE(std::isnan(confirmed.missed[i])) << "x " << x << " y " << y << ": touched";
    if (y > 4.5 && y < 5.5 && !std::isnan(split.missed[i])) {
      ++beside;
      EXPECT_FALSE(std::isnan(confirmed.missed[i])) << "x " << x << " y " << y << ": the program never came near";
    }
  }
  EXPECT_GT(beside, 70 * 200);
  EXPECT_EQ(confirmed.missed_zmap_mm2, split.missed_zmap_mm2);
  EXPECT_LT(confirmed.missed_mm2, split.missed_mm2);
}

// The rest measured as the job judges it (measure_rest_exactly): a Ø2 ball along Y 10 from X 5 to
// X 15 with its tip 0.05 over the plate's top (program Z −0.95). A cell at dY from its line is at
// √(dY² + 1.05²) − 1 from the ball: under 4 thresholds (0.08) for |dY| < 0.2528, measured so;
// farther, and in the stock it never cut (0.1 over the design), the z-map's reading stands (NaN).
// The rest stock then reads the exact figure on the plate's top.
TEST(JobChain, TheRestIsMeasuredExactlyByTheProgramsThatLeftIt) {
  const ingest::Mesh plate = testing_ingest::box(0, 0, 0, 20, 20, 5);
  const Frame frame = frame_of(plate, 1.0);
  SimParams sim;
  sim.cell_mm = 0.05;
  const Design design = design_surface(plate, frame, sim);
  simulate::ZMap stock = finishing_stock(design, frame, sim);
  gcode::Program p;
  p.items = {to(Motion::Rapid, 5, 10, 5), to(Motion::Line, 5, 10, -0.95, 300), to(Motion::Line, 15, 10, -0.95, 300),
             to(Motion::Rapid, 15, 10, 5)};
  const std::vector<ChainStep> steps{{&p, Cutter::ball(2)}};
  (void)machine_steps(stock, design, steps, gcode::MotionModel{});
  const simulate::GridSpec& g = stock.spec();
  finish::RestStock rest;
  rest.x0 = g.x(0), rest.y0 = g.y(0), rest.cell = g.cell;
  rest.nx = static_cast<int>(g.nx), rest.ny = static_cast<int>(g.ny);
  rest.z = stock.heights();
  rest.z_offset = -frame.z_shift();
  measure_rest_exactly(rest, stock, design, steps, 0.02);
  rest.check();
  int measured = 0, standing = 0;
  for (std::size_t i = 0; i < g.cells(); ++i) {
    const double x = g.x(i % g.nx), dy = std::abs(g.y(i / g.nx) - 10);
    if (x < 5.5 || x > 14.5 || (dy > 0.24 && dy < 0.27)) continue;
    const double exact = std::hypot(dy, 1.05) - 1;
    if (dy < 0.24) {
      ++measured;
      EXPECT_NEAR(rest.exact_mm[i], exact, 1e-5) << "x " << x << " dy " << dy;
      EXPECT_NEAR(rest.exact_z[i], -1.0, 1e-9);
      EXPECT_NEAR(rest.material({x, g.y(i / g.nx), 5.0}, Eigen::Vector3d::UnitZ()), exact, 1e-5);
    } else {
      ++standing;
      EXPECT_TRUE(std::isnan(rest.exact_mm[i])) << "x " << x << " dy " << dy;
    }
  }
  EXPECT_EQ(measured, 180 * 10);  // centres X 5.525 … 14.475, dY 0.025 … 0.225 either side
  EXPECT_GT(standing, 180 * 300);
  finish::RestStock other = rest;
  other.z.pop_back();
  EXPECT_THROW(measure_rest_exactly(other, stock, design, steps, 0.02), Error);
}

}  // namespace
}  // namespace millnet::job

namespace millnet::job {
namespace {

// A stock from a raster of its top: the plate's 20 × 20 grid, the raster 1 mm over the plate's top
// (5) on the left half and missing on the right: program heights 6 − 6 = 0 where it covers (the
// frame's stock top is 6: the plate + 1), the part's bottom (−6) where it does not; the departure
// then reads 5 mm below the design on the right half (the plate's top at −1), none above Z 0.
TEST(JobStock, AStockFromARasterAndHowFarItDepartsFromOneAJobCanStartFrom) {
  const ingest::Mesh plate = testing_ingest::box(0, 0, 0, 20, 20, 5);
  const Frame frame = frame_of(plate, 1.0);
  SimParams sim;
  sim.cell_mm = 0.5;
  const Design design = design_surface(plate, frame, sim);
  const simulate::GridSpec& g = design.grid;
  ingest::HeightField top;
  top.nx = static_cast<int>(g.nx), top.ny = static_cast<int>(g.ny);
  top.z.assign(g.cells(), 6.0);
  top.hit.assign(g.cells(), 0);
  for (std::size_t c = 0; c < g.cells(); ++c) top.hit[c] = g.x(c % g.nx) < 10 ? 1 : 0;
  const simulate::ZMap z = stock_from_raster(top, design, frame, sim);
  EXPECT_EQ(z.at(0, 0), 0.0);
  EXPECT_EQ(z.at(g.nx - 1, 0), frame.program_bottom());
  EXPECT_EQ(frame.program_bottom(), -6.0);
  const StockDeparture d = stock_departure(z, design);
  EXPECT_DOUBLE_EQ(d.below_design_mm, 5.0);
  EXPECT_GE(d.below_at[0], 10.0);
  EXPECT_EQ(d.above_top_mm, 0.0);
  top.z.assign(g.cells(), 6.25);  // 0.25 over the stock top
  EXPECT_DOUBLE_EQ(stock_departure(stock_from_raster(top, design, frame, sim), design).above_top_mm, 0.25);
  top.z.pop_back();
  EXPECT_THROW((void)stock_from_raster(top, design, frame, sim), millnet::Error);
}

}  // namespace
}  // namespace millnet::job

namespace millnet::job {
namespace {

// Issue 38: the block's surround. A 10 × 6 plate 4 high in a block with sides 2, 2, 1, 1: the
// surround's grid reaches one 0.25 mm cell past the block (⌈14 / 0.25⌉ + 2 = 58 by ⌈8 / 0.25⌉ + 2 =
// 34 cells), the block's cells at its top, those past it below the part. A flat Ø4 pass along the
// block's left edge at Z −3 lowers the surround there; the roughing's stock top then reads the fine
// z-map over the footprint, the surround beyond it (the pass's −3 on the block's edge, not the
// block's top), and with no surround the block's top beyond the footprint.
TEST(JobChain, TheBlocksSurroundHoldsTheStockBeyondTheFootprint) {
  const ingest::Mesh plate = testing_ingest::box(0, 0, 0, 10, 6, 4);
  const Frame frame = frame_of(plate, 1.0);  // stock top: part z 5
  SimParams sim;
  sim.cell_mm = 0.1;
  simulate::ZMap s = block_surround(frame, {2, 2, 1, 1}, 0.0, sim);
  const simulate::GridSpec& g = s.spec();
  ASSERT_EQ(g.nx, 58U);
  ASSERT_EQ(g.ny, 34U);
  EXPECT_DOUBLE_EQ(g.x0, -2.25);
  EXPECT_DOUBLE_EQ(g.y0, -1.25);
  EXPECT_DOUBLE_EQ(s.at(0, 10), frame.program_bottom() - 1.0);  // centre x −2.125: past the block
  EXPECT_DOUBLE_EQ(s.at(1, 10), 0.0);                           // centre x −1.875: the block
  EXPECT_DOUBLE_EQ(s.at(57, 33), frame.program_bottom() - 1.0);
  gcode::Program p;
  p.items = {to(Motion::Rapid, -2, -3, 5), to(Motion::Rapid, -2, -3, -3), to(Motion::Line, -2, 9, -3, 500)};
  machine_surround(s, {{&p, Cutter::flat(4)}});
  EXPECT_DOUBLE_EQ(s.at(1, 10), -3.0);  // x −1.875, within the Ø4's reach of x −2
  EXPECT_DOUBLE_EQ(s.at(20, 10), 0.0);  // x 2.875: beyond it
  const Design design = design_surface(plate, frame, sim);
  const simulate::ZMap fine = block_stock(design, sim, -0.5);  // the footprint, faced to Z −0.5
  const ingest::HeightField with = stock_top_field(fine, frame, -2, -1, 12, 7, 0.5, &s);
  const ingest::HeightField without = stock_top_field(fine, frame, -2, -1, 12, 7, 0.5);
  ASSERT_EQ(with.nx, 29);
  const auto at = [](const ingest::HeightField& f, double x, double y) {
    return f.z[static_cast<std::size_t>(std::lround((y - f.y0) / 0.5)) * static_cast<std::size_t>(f.nx) +
               static_cast<std::size_t>(std::lround((x - f.x0) / 0.5))];
  };
  EXPECT_DOUBLE_EQ(at(with, 5, 3), 4.5);  // the footprint: −0.5 below the stock top at 5
  EXPECT_DOUBLE_EQ(at(without, 5, 3), 4.5);
  EXPECT_DOUBLE_EQ(at(with, -2, 3), 2.0);  // the block's edge, where the pass went: Z −3
  EXPECT_DOUBLE_EQ(at(with, -1.5, 3), 2.0);
  EXPECT_DOUBLE_EQ(at(with, 11, 3), 5.0);  // the block untouched
  EXPECT_DOUBLE_EQ(at(without, -2, 3), 5.0);
}

}  // namespace
}  // namespace millnet::job

// /simulate/cells_per_pass: a cell from the passes' spacing keeps the rest test's block and stride
// near 0.125 mm (5 cells of the default 0.025 mm) and its Ra centres near ra_spacing_mm; a cell
// set directly keeps the 5-cell block, as the shipped labels were computed.
namespace millnet::job {
TEST(JobSimParams, ACellFromThePassesKeepsTheRestTestsBlockInMillimetres) {
  SimParams sim;
  sim.ra_spacing_mm = 0.1;
  const tooling::Cutter ball = tooling::Cutter::ball(2);
  for (const double cell : {0.025, 0.04, 0.0693}) {
    sim.cell_mm = cell;
    sim.pass_spacing_mm = 0;
    EXPECT_EQ(sim.metrics_options(ball).reach_every, 5u) << cell;
    sim.pass_spacing_mm = 5 * cell;
  }
  const std::pair<double, std::size_t> rule[] = {{0.025, 5}, {0.03995, 3}, {0.0333, 4}, {0.0693, 2}, {0.3, 1}};
  for (const auto& [cell, k] : rule) {
    sim.cell_mm = cell;
    sim.pass_spacing_mm = 5 * cell;
    EXPECT_EQ(sim.metrics_options(ball).reach_every, k) << cell;  // round(0.125 / cell), at least 1
    EXPECT_EQ(sim.metrics_options(ball).ra_every, static_cast<std::size_t>(std::max(1.0, std::round(0.1 / cell))));
  }
}
}  // namespace millnet::job
