// job/operations: a roughing program's pre-drilling split into a drilling operation with the drill's
// speed and feed, the job program's tool changes (T M6, G43 H in the Fanuc dialect) read back and
// split tool by tool, the drill and the reaching tool chosen from a library, inline tools numbered,
// and the holder clearance against hand-computed heights.
#include "millnet/job/finishing.hpp"
#include "millnet/job/operations.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"
#include "testing/moves.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <string>
#include <variant>

using namespace millnet;
using gcode::Motion;

namespace {

/// A roughing program as pocket's build_program lays out a pre-drilled entry: safe Z, the drilling
/// block (its comment, spindle, holes, spindle off, the end mill's comment and pause), then a level.
gcode::Program predrilled_rough() {
  gcode::Program p;
  p.header = {"roughing"};
  p.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}),
             gcode::Comment{"PRE-DRILL: load a drill of diameter 10 mm"},
             gcode::Spindle{gcode::SpindleDir::CW, 9000},
             gcode::Comment{"pre-drill"},
             millnet::testing::move(Motion::Rapid, {20, 20, 5}, 0, gcode::kXYZ, 1),
             millnet::testing::move(Motion::Rapid, {20, 20, 1}, 0, gcode::kXYZ, 1),
             millnet::testing::move(Motion::Line, {20, 20, -6}, 300, gcode::kXYZ, 1),
             millnet::testing::move(Motion::Rapid, {20, 20, 5}, 0, gcode::kXYZ, 1),
             gcode::Spindle{gcode::SpindleDir::Off, 9000},
             gcode::Comment{"change to the end mill of diameter 10 mm, then resume"},
             gcode::Pause{false},
             gcode::Spindle{gcode::SpindleDir::CW, 9000},
             millnet::testing::move(Motion::Rapid, {20, 20, 1}),
             millnet::testing::move(Motion::Line, {20, 20, -6}, 300),
             millnet::testing::move(Motion::Line, {30, 20, -6}, 1200),
             millnet::testing::move(Motion::Rapid, {30, 20, 5}),
             gcode::Spindle{gcode::SpindleDir::Off, 9000}};
  return p;
}

tooling::Tool tool(std::string id, tooling::ToolType type, double d, int number, double stickout = 0) {
  tooling::Tool t;
  t.id = std::move(id);
  t.type = type;
  t.diameter_mm = d;
  t.corner_radius_mm = type == tooling::ToolType::Ball ? d / 2 : 0;
  t.number = number;
  t.stickout_mm = stickout;
  return t;
}

template <class T>
std::size_t count(const gcode::Program& p) {
  std::size_t n = 0;
  for (const gcode::Item& i : p.items) n += std::holds_alternative<T>(i) ? 1U : 0U;
  return n;
}

}  // namespace

TEST(JobOperations, PredrillingBecomesADrillingOperationAtTheDrillsSpeedAndFeed) {
  const gcode::Program rough = predrilled_rough();
  ASSERT_TRUE(job::predrills(rough));
  const tooling::Tool mill = tool("em10", tooling::ToolType::Flat, 10, 3);
  const tooling::Tool drill = tool("dr10", tooling::ToolType::Drill, 10, 10);
  EXPECT_THROW((void)job::roughing_operations(rough, mill, nullptr, {}), Error);
  const auto ops = job::roughing_operations(rough, mill, &drill, {1200, 240});
  ASSERT_EQ(ops.size(), 2U);
  EXPECT_EQ(ops[0].name, "drilling");
  EXPECT_EQ(ops[0].tool.id, "dr10");
  EXPECT_EQ(count<gcode::Move>(ops[0].program), 4U);  // the hole's four moves, nothing else
  const auto& on = std::get<gcode::Spindle>(ops[0].program.items.front());
  EXPECT_EQ(on.rpm, 1200);
  for (const gcode::Item& i : ops[0].program.items) {
    if (const auto* m = std::get_if<gcode::Move>(&i); m && m->motion == Motion::Line) {
      EXPECT_EQ(m->feed, 240);
    }
  }
  EXPECT_EQ(ops[1].name, "roughing");
  EXPECT_EQ(count<gcode::Move>(ops[1].program), 5U);  // safe Z + the level's four
  EXPECT_EQ(count<gcode::Pause>(ops[1].program), 0U);
  EXPECT_EQ(count<gcode::Comment>(ops[1].program), 0U);
  EXPECT_EQ(count<gcode::Spindle>(ops[1].program), 2U);  // the end mill's on and off
  // Without pre-drilling: the roughing alone, untouched.
  gcode::Program plain;
  plain.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}),
                 millnet::testing::move(Motion::Line, {0, 0, -1}, 100)};
  const auto one = job::roughing_operations(plain, mill, nullptr, {});
  ASSERT_EQ(one.size(), 1U);
  EXPECT_EQ(one[0].program.items.size(), 2U);
}

TEST(JobOperations, TheJobProgramChangesToolsAndReadsBackToolByTool) {
  const tooling::Tool mill = tool("em10", tooling::ToolType::Flat, 10, 3);
  tooling::Tool drill = tool("dr10", tooling::ToolType::Drill, 10, 10);
  drill.length_offset = 21;
  auto ops = job::roughing_operations(predrilled_rough(), mill, &drill, {1200, 240});
  gcode::Program finishing;
  finishing.items = {gcode::Spindle{gcode::SpindleDir::CW, 18000}, millnet::testing::move(Motion::Rapid, {0, 0, 5}),
                     millnet::testing::move(Motion::Line, {0, 0, -2}, 1900),
                     millnet::testing::move(Motion::Rapid, {0, 0, 5}), gcode::Spindle{gcode::SpindleDir::Off, 0}};
  ops.push_back({"finishing", tool("bn2", tooling::ToolType::Ball, 2, 7), finishing});
  const gcode::Program job = job::job_program(ops, {"part"});
  const std::string text = gcode::write(job, gcode::fanuc());
  EXPECT_NE(text.find("T10 M6"), std::string::npos) << text;
  EXPECT_NE(text.find("G43 H21"), std::string::npos) << text;  // the drill's own length-offset register
  EXPECT_NE(text.find("T3 M6"), std::string::npos);
  EXPECT_NE(text.find("G43 H3"), std::string::npos);
  EXPECT_NE(text.find("T7 M6"), std::string::npos);
  EXPECT_LT(text.find("T10 M6"), text.find("T3 M6"));
  EXPECT_LT(text.find("T3 M6"), text.find("T7 M6"));
  const gcode::Program back = gcode::read(text, "job.nc");
  const auto runs = job::split_at_tool_changes(back);
  ASSERT_EQ(runs.size(), 3U);
  EXPECT_EQ(runs[0].tool_number, 10);
  EXPECT_EQ(runs[1].tool_number, 3);
  EXPECT_EQ(runs[2].tool_number, 7);
  EXPECT_EQ(count<gcode::Move>(runs[0].program), 4U);
  EXPECT_EQ(count<gcode::Move>(runs[1].program), 5U);
  EXPECT_EQ(count<gcode::Move>(runs[2].program), 3U);
  EXPECT_EQ(runs[1].program.items.size(), runs[1].program.source_line.size());
  // One operation alone: its tool change first.
  const std::string alone = gcode::write(job::operation_program(ops[2], {"finishing"}), gcode::linuxcnc());
  EXPECT_NE(alone.find("T7 M6"), std::string::npos);
  // A tool without a number cannot be changed to.
  ops[2].tool.number = 0;
  EXPECT_THROW((void)job::job_program(ops, {}), Error);
  const auto renumbered = job::numbered(ops);
  EXPECT_EQ(renumbered[2].tool.number, 22);  // above every number and H register in use
  const auto tools = job::tools_of(renumbered);
  ASSERT_EQ(tools.size(), 3U);
  EXPECT_EQ(tools[0].id, "dr10");
  EXPECT_DOUBLE_EQ(job::deepest_z(predrilled_rough()), -6);
}

TEST(JobOperations, InlineToolsSharingAShapeShareANumber) {
  std::vector<job::Operation> ops{{"a", tool("", tooling::ToolType::Ball, 2, 0), {}},
                                  {"b", tool("em6", tooling::ToolType::Flat, 6, 4), {}},
                                  {"c", tool("", tooling::ToolType::Ball, 2, 0), {}},
                                  {"d", tool("", tooling::ToolType::Ball, 3, 0), {}}};
  const auto n = job::numbered(ops);
  EXPECT_EQ(n[0].tool.number, 5);
  EXPECT_EQ(n[1].tool.number, 4);
  EXPECT_EQ(n[2].tool.number, 5);
  EXPECT_EQ(n[3].tool.number, 6);
}

TEST(JobOperations, TheDrillAndTheReachingToolComeFromTheLibrary) {
  std::vector<tooling::Tool> lib{
      tool("dr8-long", tooling::ToolType::Drill, 8, 11, 80), tool("dr10-short", tooling::ToolType::Drill, 10, 12, 15),
      tool("dr10", tooling::ToolType::Drill, 10, 10, 100),   tool("dr10-mid", tooling::ToolType::Drill, 10, 13, 40),
      tool("dr12", tooling::ToolType::Drill, 12, 14, 100),   tool("bn6-35", tooling::ToolType::Ball, 6, 8, 35),
      tool("bn6-60", tooling::ToolType::Ball, 6, 15, 60),    tool("bn6-45", tooling::ToolType::Ball, 6, 16, 45)};
  const tooling::Tool em10 = tool("em10", tooling::ToolType::Flat, 10, 3, 50);
  // The largest drill not wider than the end mill that reaches, then the shortest.
  EXPECT_EQ(job::drill_for(lib, em10, 30)->id, "dr10-mid");
  EXPECT_EQ(job::drill_for(lib, em10, 10)->id, "dr10-short");
  EXPECT_EQ(job::drill_for(lib, em10, 90)->id, "dr10");
  EXPECT_EQ(job::drill_for(lib, em10, 101), nullptr);
  EXPECT_EQ(job::drill_for(lib, tool("em3", tooling::ToolType::Flat, 3, 1), 5), nullptr);  // Ø8 is wider than Ø3
  EXPECT_EQ(job::drill_for(lib, tool("em16", tooling::ToolType::Flat, 16, 1), 5)->id, "dr12");
  // The configured ball reaches 30 mm; for 40 mm the shortest library ball Ø6 that does (45), for
  // 61 none.
  const tooling::Tool& short_ball = lib[5];
  EXPECT_EQ(job::tool_that_reaches(lib, short_ball, 30), &short_ball);
  EXPECT_EQ(job::tool_that_reaches(lib, short_ball, 40)->id, "bn6-45");
  EXPECT_EQ(job::tool_that_reaches(lib, short_ball, 50)->id, "bn6-60");
  EXPECT_EQ(job::tool_that_reaches(lib, short_ball, 61), nullptr);
  EXPECT_EQ(job::tool_that_reaches(lib, tool("x", tooling::ToolType::Ball, 6, 0), 500)->id, "x");  // no stick-out
}

TEST(JobOperations, AToolGivenByItsShapeTakesTheLongestLibraryToolOfThatShape) {
  std::vector<tooling::Tool> lib{
      tool("bn6-35", tooling::ToolType::Ball, 6, 8, 35), tool("bn6-60", tooling::ToolType::Ball, 6, 15, 60),
      tool("bn6-none", tooling::ToolType::Ball, 6, 16, 0), tool("em6-80", tooling::ToolType::Flat, 6, 17, 80),
      tool("bn8-90", tooling::ToolType::Ball, 8, 18, 90)};
  EXPECT_EQ(job::longest_of_shape(lib, tooling::ToolType::Ball, 6, 3)->id, "bn6-60");
  EXPECT_EQ(job::longest_of_shape(lib, tooling::ToolType::Flat, 6, 0)->id, "em6-80");
  EXPECT_EQ(job::longest_of_shape(lib, tooling::ToolType::Ball, 6.5, 3.25), nullptr);  // no Ø6.5
  EXPECT_EQ(job::longest_of_shape(lib, tooling::ToolType::Bull, 6, 1), nullptr);       // no bull
  EXPECT_EQ(job::longest_of_shape({lib[2]}, tooling::ToolType::Ball, 6, 3), nullptr);  // no stick-out stated
}

TEST(JobOperations, HolderClearanceAgainstAStep) {
  // A 20 x 20 mm plate at Z -10 with a step up to Z -5 for x ≥ 10, cells of 0.1 mm.
  simulate::GridSpec g;
  g.cell = 0.1;
  g.nx = g.ny = 200;
  std::vector<double> design(g.cells());
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) design[iy * g.nx + ix] = g.x(ix) >= 10 ? -5 : -10;
  tooling::Tool t = tool("bn2", tooling::ToolType::Ball, 2, 7, 4);
  t.holder_diameter_mm = 10;  // radius 5; conservative by the 0.5 mm cells' diagonal, 0.71 mm
  auto run_at = [&](double x) {
    gcode::Program p;
    p.items = {millnet::testing::move(Motion::Rapid, {x, 2, 5}), millnet::testing::move(Motion::Line, {x, 2, -10}, 100),
               millnet::testing::move(Motion::Line, {x, 18, -10}, 100)};
    return job::holder_clearance(p, t, g, design);
  };
  const job::HolderClearance far = run_at(3);  // the step 7 mm away: only the plate under the holder
  EXPECT_TRUE(far.checked);
  EXPECT_DOUBLE_EQ(far.deepest_tip_z, -10);
  EXPECT_DOUBLE_EQ(far.reach_needed_mm, 0);
  EXPECT_DOUBLE_EQ(far.min_clearance_mm, 4);
  const job::HolderClearance near = run_at(6);  // 4 mm from the step: its top is under the holder
  EXPECT_DOUBLE_EQ(near.reach_needed_mm, 5);
  EXPECT_DOUBLE_EQ(near.min_clearance_mm, -1);  // stick-out 4 < 5: the holder hits the step
  EXPECT_DOUBLE_EQ(near.worst[2], -10);
  t.holder_diameter_mm = 0;
  EXPECT_FALSE(job::holder_clearance({}, t, g, design).checked);
}

// Issue 38: the semi-finishing ball — larger than the finisher, no larger than the end mill, flutes
// that take the stock left, a stick-out that reaches; the smallest, then the shortest.
TEST(JobOperations, TheSemiFinishingBallTakesTheStockLeftAndReaches) {
  auto ball = [](std::string id, double d, double flutes, double stickout) {
    tooling::Tool t = tool(std::move(id), tooling::ToolType::Ball, d, 1, stickout);
    t.flute_length_mm = flutes;
    return t;
  };
  const std::vector<tooling::Tool> lib{ball("bn2", 2, 3, 45),
                                       ball("bn4", 4, 6, 20),
                                       ball("bn6-35", 6, 10, 35),
                                       ball("bn6-50", 6, 10, 50),
                                       ball("bn10", 10, 16, 45),
                                       ball("bn12", 12, 20, 60),
                                       tool("em8", tooling::ToolType::Flat, 8, 2, 60)};
  const tooling::Tool& bn2 = lib[0];
  const tooling::Tool em10 = tool("em10", tooling::ToolType::Flat, 10, 3, 50);
  EXPECT_EQ(job::semi_finishing_tool(lib, bn2, em10, 5, 15)->id, "bn4");     // 6 mm flutes take 5
  EXPECT_EQ(job::semi_finishing_tool(lib, bn2, em10, 5, 30)->id, "bn6-35");  // bn4 reaches 20
  EXPECT_EQ(job::semi_finishing_tool(lib, bn2, em10, 5, 40)->id, "bn6-50");  // the Ø6 that reaches
  EXPECT_EQ(job::semi_finishing_tool(lib, bn2, em10, 12, 30)->id, "bn10");   // flutes of 16
  EXPECT_EQ(job::semi_finishing_tool(lib, bn2, em10, 17, 30), nullptr);      // Ø12 is wider than the end mill
  EXPECT_EQ(job::semi_finishing_tool(lib, lib[4], em10, 5, 30), nullptr);    // none larger than Ø10 and ≤ Ø10
  // The step that leaves a 0.1 mm cusp with a Ø6 ball: 2·√(2·3·0.1 − 0.01) = 1.5362 mm; the cusp
  // of that step, h = r − √(r² − (s/2)²), is the 0.1 mm asked for.
  const double s = job::scallop_step(3, 0.1);
  EXPECT_NEAR(s, 2 * std::sqrt(0.59), 1e-12);
  EXPECT_NEAR(3 - std::sqrt(9 - s * s / 4), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(job::scallop_step(3, 5), 6.0);  // a cusp above the radius: the diameter
}

// The drilling operation's holes are drilling cycles: a hole 7 mm deep from R 1 is drilled in one
// feed by a Ø10 drill (G81) and pecked by a Ø2 (deeper than 3 × 2 mm: G83, Q 2 mm): feeds to −1,
// −3, −5, each followed by a rapid to R and back down to 0.254 mm above, then to the bottom −6,
// and back to Z 5. Written, the LinuxCNC program says so in one block and reads back to the moves.
TEST(JobOperations, TheHolesAreDrilledByCyclesAndDeepHolesPecked) {
  const tooling::Tool mill = tool("em10", tooling::ToolType::Flat, 10, 3);
  const tooling::Tool big = tool("dr10", tooling::ToolType::Drill, 10, 10);
  const tooling::Tool small = tool("dr2", tooling::ToolType::Drill, 2, 11);
  const auto g81 = job::roughing_operations(predrilled_rough(), mill, &big, {1200, 240});
  const std::string text81 = gcode::write(g81[0].program, gcode::linuxcnc());
  EXPECT_NE(text81.find("G0 X20 Y20 Z5\nG98 G81 X20 Y20 Z-6 R1 F240\nG80\n"), std::string::npos) << text81;
  const auto g83 = job::roughing_operations(predrilled_rough(), mill, &small, {4000, 100});
  std::vector<double> zs;
  for (const gcode::Item& i : g83[0].program.items)
    if (const auto* m = std::get_if<gcode::Move>(&i)) {
      zs.push_back(m->motion == Motion::Line ? -100 + m->to[2] : m->to[2]);  // feeds marked by −100
      EXPECT_EQ(m->cycle, m == &std::get<gcode::Move>(g83[0].program.items[1]) ? 0 : 83);
    }
  const std::vector<double> want{5, 1, -101, 1, -0.746, -103, 1, -2.746, -105, 1, -4.746, -106, 5};
  ASSERT_EQ(zs.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k) EXPECT_NEAR(zs[k], want[k], 1e-12) << k;
  const std::string text83 = gcode::write(g83[0].program, gcode::linuxcnc());
  EXPECT_NE(text83.find("G98 G83 X20 Y20 Z-6 R1 Q2 F100\nG80\n"), std::string::npos) << text83;
  const gcode::Program back = gcode::read(text83, "g83.nc");
  EXPECT_EQ(count<gcode::Move>(back), want.size());
}

// The order a job tries the strategies in (job::ranked_clean): the chosen one first, then the others
// by rank; a gouging one and an unranked one left out.
TEST(RankedClean, TheChosenFirstThenTheRankingWithoutGougingOrUnranked) {
  using finish::Strategy;
  std::vector<job::StrategyOutcome> o(5);
  const Strategy slots[] = {Strategy::SlopeMode, Strategy::Raster, Strategy::ScallopMode, Strategy::Waterline,
                            Strategy::Equidistant};
  const int ranks[] = {2, 5, 3, 1, 0};
  for (std::size_t i = 0; i < 5; ++i) o[i].strategy = slots[i], o[i].rank = ranks[i];
  o[1].simulated = true, o[1].surface.gouged = true;  // rank 5, gouges
  const auto r = job::ranked_clean(o, o[3]);          // the first of the ranking
  ASSERT_EQ(r.size(), 3U);
  EXPECT_EQ(r[0].strategy, Strategy::Waterline);
  EXPECT_EQ(r[1].strategy, Strategy::SlopeMode);
  EXPECT_EQ(r[2].strategy, Strategy::ScallopMode);
}

namespace {

double segment_distance(double px, double py, const gcode::Point3& a, const gcode::Point3& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((px - a[0]) * dx + (py - a[1]) * dy) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(px - (a[0] + t * dx), py - (a[1] + t * dy));
}

/// The feed moves of `p` as segments (from the previous position), with their Z.
std::vector<std::pair<gcode::Point3, gcode::Point3>> feed_segments(const gcode::Program& p) {
  std::vector<std::pair<gcode::Point3, gcode::Point3>> out;
  gcode::Point3 at{};
  bool known = false;
  for (const gcode::Item& i : p.items) {
    const auto* m = std::get_if<gcode::Move>(&i);
    if (m == nullptr) continue;
    if (known && m->motion == Motion::Line) out.emplace_back(at, m->to);
    at = m->to, known = true;
  }
  return out;
}

}  // namespace

// Issue 38 (a stock "pre-squared or not"): a sawn blank's top faced to Z 0 — every point of the
// stock rectangle under the last level's passes (a brute-force oracle on a 0.25 mm raster), levels
// no deeper than asked, the hand-computed number of passes, every rapid below the blank's top and
// every step between passes off the stock.
TEST(JobOperations, FacingTakesTheSawnTopToZ0OverTheWholeStockAndMovesDownOnlyBesideIt) {
  const tooling::Tool mill = tool("em10", tooling::ToolType::Flat, 10, 1);
  job::FacingSpec s;
  s.x0 = -5, s.y0 = -5, s.x1 = 105, s.y1 = 55;
  s.blank_top = 2.5, s.max_depth_mm = 1.0, s.stepover_mm = 7.5, s.safe_z = 5;
  s.rpm = 9000, s.feed_mm_min = 1500, s.plunge_feed_mm_min = 300;
  const job::Operation op = job::facing_operation(mill, s);
  EXPECT_EQ(op.name, "facing");
  ASSERT_EQ(count<gcode::Spindle>(op.program), 2U);
  // 2.5 mm in levels of at most 1 mm: three, at 2.5·2/3, 2.5/3 and 0. Across the 60 mm side, passes
  // from y0 + R − R/10 = −0.5 to y1 − R + R/10 = 50.5: 51 mm at most 7.5 apart, ⌈51 / 7.5⌉ + 1 = 8.
  const auto segs = feed_segments(op.program);
  std::map<long, int> passes;  // per level (Z in µm), the moves across the stock's length
  double lowest = 1e9;
  for (const auto& [a, b] : segs) {
    lowest = std::min(lowest, b[2]);
    if (std::abs(b[0] - a[0]) > 110) ++passes[std::lround(b[2] * 1000)];
  }
  EXPECT_DOUBLE_EQ(lowest, 0.0);
  ASSERT_EQ(passes.size(), 3U);
  EXPECT_EQ(passes[0], 8);
  EXPECT_EQ(passes[833], 8);
  EXPECT_EQ(passes[1667], 8);
  // The oracle: every raster point of the stock within the radius of a pass at Z 0.
  std::size_t unfaced = 0;
  for (double y = s.y0; y <= s.y1 + 1e-9; y += 0.25)
    for (double x = s.x0; x <= s.x1 + 1e-9; x += 0.25) {  // O(points · segments): a test's 100,000 × 50
      double best = 1e9;
      for (const auto& [a, b] : segs)
        if (a[2] == 0 && b[2] == 0) best = std::min(best, segment_distance(x, y, a, b));
      unfaced += best < 5 - 1e-9 ? 0U : 1U;
    }
  EXPECT_EQ(unfaced, 0U);
  // Below the blank's top, the tool arrives beside the stock: a rapid ends there only off the stock
  // grown by the radius, and the steps between passes run there too.
  const auto off = [&](const gcode::Point3& p) {
    return p[0] <= s.x0 - 5 || p[0] >= s.x1 + 5 || p[1] <= s.y0 - 5 || p[1] >= s.y1 + 5;
  };
  for (const gcode::Item& i : op.program.items)
    if (const auto* m = std::get_if<gcode::Move>(&i); m != nullptr && m->motion == Motion::Rapid && m->to[2] < 2.5) {
      EXPECT_TRUE(off(m->to)) << m->to[0] << " " << m->to[1] << " " << m->to[2];
    }
  for (const auto& [a, b] : segs) {
    if (std::abs(b[1] - a[1]) > 1e-9) {
      EXPECT_TRUE(off(a) && off(b)) << a[0] << " → " << b[0];
    }
  }
  // A stock deeper than wide is faced along Y; a blank top at the safe height or a stepover beyond
  // the diameter is refused.
  job::FacingSpec tall = s;
  tall.x1 = 35, tall.y1 = 95;
  for (const auto& [a, b] : feed_segments(job::facing_operation(mill, tall).program))
    EXPECT_LT(std::abs(b[0] - a[0]), 40.1);
  job::FacingSpec high = s;
  high.blank_top = 5;
  EXPECT_THROW((void)job::facing_operation(mill, high), Error);
  job::FacingSpec wide = s;
  wide.stepover_mm = 10.5;
  EXPECT_THROW((void)job::facing_operation(mill, wide), Error);
}
