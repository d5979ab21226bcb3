// Pocket work estimates (pocket/work.hpp, issue 12 §1) against hand-computed counts, and the guard:
// refused over the limit, not refused just under it.
#include "millnet/core/error.hpp"
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpoints.hpp"
#include "millnet/pocket/work.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace millnet::pocket;
using millnet::WorkLimits;

namespace {
Region square(double side) { return Region{{{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}}, {}}; }
SomSpec som(double spacing) {
  SomSpec s;
  s.frame.spacing = spacing;
  return s;
}
CutParams cut(double d, double stepover) {
  CutParams c;
  c.tool.diameter = d;
  c.stepover = stepover;
  return c;
}
std::string refusal(const Region& r, const CutParams& c, const PlannerSpec& s, const WorkLimits& l) {
  try {
    check_work(r, c, s, l);
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(PocketWork, ToolPointGridOfA100mmSquareAtStepover1Is101Squared) {
  // Grid rows and columns 0..100 at spacing 1 from the origin: 101 × 101 = 10,201 points visited;
  // the tool points are a subset (D 10 keeps 91 × 91 of them).
  const auto e = estimate_work(square(100), cut(10, 1), som(1));
  ASSERT_EQ(e.size(), 4U);
  EXPECT_EQ(e[0].count, 101.0 * 101.0);
  EXPECT_EQ(e[0].unit, "tool points");
  EXPECT_EQ(e[0].bytes, 24.0 * 101 * 101);
  EXPECT_EQ(e[0].cause, "stepover 1 mm over a 100 × 100 mm pocket");
  // The estimate bounds the real count from above.
  const ToolPoints tp = make_tool_points(square(100), som(1).frame, 5);
  EXPECT_LE(static_cast<double>(tp.pts.size()), e[0].count);
  EXPECT_EQ(tp.pts.size(), 91U * 91U);
  // Ring: node_factor 2 × the grid points (an upper bound of 2 × the 8,281 tool points).
  EXPECT_EQ(e[1].unit, "SOM ring nodes");
  EXPECT_EQ(e[1].count, 2.0 * 101 * 101);
  EXPECT_EQ(e[1].cause, "node_factor 2 × the tool points of stepover 1 mm over a 100 × 100 mm pocket");
  // The run's time: the ring node pulls and winner searches of its schedule, checked against
  // max_pairs (issue 42).
  EXPECT_EQ(e[2].unit, "ring node pulls and winner searches");
  EXPECT_EQ(e[2].count, som_node_steps(101.0 * 101, SomParams{}));
  EXPECT_TRUE(e[2].pairs);
  // Feed map: D/10 = 1 mm cells over the box grown by R + g = 6 on each side: 112 × 112.
  EXPECT_EQ(e[3].unit, "feed-map cells");
  EXPECT_EQ(e[3].count, 112.0 * 112.0);
}

// Issue 42 §7/5: the SOM on a 2 × 2 m pocket at stepover 5 (160,801 tool points) never finished;
// its tour takes ~10 s (3.7e8 steps of its schedule pass the limit: docs/roughing.md), and a
// pocket 5 times as wide is refused by them, naming the stepover and what to change.
TEST(PocketWork, TheSomOfA2mPocketPassesAndOfA10mPocketIsRefusedByItsSteps) {
  EXPECT_EQ(refusal(square(2000), cut(10, 5), som(5), WorkLimits{1e7, 8e9, 5e9}), "");
  const std::string msg = refusal(square(10000), cut(10, 5), som(5), WorkLimits{1e8, 8e9, 5e9});
  EXPECT_NE(msg.find("stepover 5 mm over a 10000 × 10000 mm pocket (its SOM's adaptation passes; a larger stepover "
                     "or another planner) makes 9.3e9 ring node pulls and winner searches"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("; the limit is 5.0e9 (--max-pairs, /limits/max_pairs)"), std::string::npos) << msg;
}

TEST(PocketWork, IssueExampleStepover0001IsRefusedWithTheDocumentedLine) {
  const std::string msg = refusal(square(100), cut(10, 0.001), som(0.001), WorkLimits{});
  EXPECT_NE(msg.find("stepover 0.001 mm over a 100 × 100 mm pocket makes 1.0e10 tool points (≈ 240 GB); the limit "
                     "is 2.0e7 (--max-work, /limits/max_work)"),
            std::string::npos)
      << msg;
}

TEST(PocketWork, IssueExampleVertex1kmAwayIsRefusedByItsFeedMap) {
  const Region r{{{0, 0, 0}, {1000000, 0, 0}, {100, 100, 0}, {0, 100, 0}}, {}};
  // The offset planner: the SOM's adaptation steps refuse it first (issue 42).
  const std::string msg = refusal(r, cut(10, 5), OffsetSpec{}, WorkLimits{});
  EXPECT_NE(msg.find("feed_grid 1 mm over a 1000000 × 100 mm pocket makes 1.1e8 feed-map cells"), std::string::npos)
      << msg;
  EXPECT_NE(refusal(r, cut(10, 5), som(5), WorkLimits{}).find("makes 9.7e9 ring node pulls and winner searches"),
            std::string::npos);
}

TEST(PocketWork, JustUnderTheLimitIsNotRefusedJustOverIs) {
  // 100 mm square, stepover 1: 10,201 grid points, 20,402 ring nodes, 12,544 feed-map cells.
  EXPECT_EQ(refusal(square(100), cut(10, 1), som(1), WorkLimits{20402, 1e9}), "");
  EXPECT_NE(refusal(square(100), cut(10, 1), som(1), WorkLimits{20401, 1e9}).find("makes 2.0402e4 SOM ring nodes"),
            std::string::npos);
  // The zigzag planner has no ring: its largest figure is the feed map.
  ZigzagSpec z;
  z.zigzag.angle_deg = 0.0;
  EXPECT_EQ(refusal(square(100), cut(10, 1), z, WorkLimits{12544, 1e9}), "");
  EXPECT_NE(refusal(square(100), cut(10, 1), z, WorkLimits{12543, 1e9}).find("feed-map cells"), std::string::npos);
  EXPECT_NE(refusal(square(100), cut(10, 1), som(1), WorkLimits{1e9, 24.0 * 10201 - 1}).find("memory limit"),
            std::string::npos);
}

TEST(PocketWork, ZigzagCountsScanLinesPerDirection) {
  ZigzagSpec z;
  z.zigzag.angle_deg = 0.0;
  // Diagonal 100√2 = 141.4 at stepover 1: 142 lines, one direction.
  auto e = estimate_work(square(100), cut(10, 1), z);
  ASSERT_EQ(e.size(), 2U);
  EXPECT_EQ(e[0].unit, "zigzag scan lines");
  EXPECT_EQ(e[0].count, 142.0);
  // Searching: ⌈180 / 5⌉ = 36 directions + one per boundary segment (4).
  z.zigzag.angle_deg.reset();
  e = estimate_work(square(100), cut(10, 1), z);
  EXPECT_EQ(e[0].count, 142.0 * 40);
}

TEST(PocketWork, RotatedGridCountsTheRotatedBox) {
  SomSpec s = som(1);
  s.frame.angle_deg = 45;
  const double n = estimate_work(square(100), cut(10, 1), s)[0].count;
  // The square's box in the rotated frame is 100√2 wide both ways: ≈ 143² points.
  EXPECT_GT(n, 141.0 * 141.0);
  EXPECT_LE(n, 144.0 * 144.0);
  EXPECT_LE(static_cast<double>(make_tool_points(square(100), s.frame, 5).pts.size()), n);
}

TEST(PocketWork, AdaptiveRasterIsDOver80UnlessThatPassesTenMillionCells) {
  // A 100 mm square with D 10: the box grown by D is 120 mm, at D/80 = 0.125 mm 961 × 961 cells
  // (ceil(120 / 0.125) + 1 in the planner's grid) ≤ 10⁷: D/80. A 500 mm square: 4161² ≈ 1.7·10⁷ cells
  // at D/80, so D/40 (0.25 mm). A raster given in the config is kept.
  AdaptiveSpec a;
  EXPECT_DOUBLE_EQ(adaptive_raster_mm(square(100), cut(10, 5), a.adaptive), 0.125);
  EXPECT_DOUBLE_EQ(adaptive_raster_mm(square(500), cut(10, 5), a.adaptive), 0.25);
  // The work estimate counts the raster the planner will make: (120 / 0.125)² and (520 / 0.25)².
  EXPECT_DOUBLE_EQ(estimate_work(square(100), cut(10, 5), a)[0].count, 960.0 * 960.0);
  EXPECT_DOUBLE_EQ(estimate_work(square(500), cut(10, 5), a)[0].count, 2080.0 * 2080.0);
  a.adaptive.raster_mm = 0.5;
  EXPECT_DOUBLE_EQ(adaptive_raster_mm(square(500), cut(10, 5), a.adaptive), 0.5);
  EXPECT_DOUBLE_EQ(estimate_work(square(500), cut(10, 5), a)[0].count, 1040.0 * 1040.0);
}
