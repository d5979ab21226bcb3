// The machining facade on the three bench pockets with a simple reference plan (row-by-row over
// the tool points, broken where a move would gouge), checked by the independent G-code replay.
#include "testing/program_text.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/tolerances.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include "offset.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using namespace millnet::pocket;
using millnet::testing::to_replay;
namespace {

/// Reference plan for the tests: boustrophedon rows of tool points; a new chain wherever the
/// next move is not clear (Clearance::move_ok) — deliberately naive, not a planner.
PlanResult row_plan(const Region& r, const CutParams& cut) {
  PlanResult plan;
  plan.planner = "rows";
  GridFrame f;
  f.spacing = cut.stepover;
  plan.tool_points = make_tool_points(r, f, cut.clearance());
  if (plan.tool_points.pts.empty()) {
    plan.status = PlanStatus::NoToolPoints;
    plan.message = "no tool point fits";
    return plan;
  }
  const Clearance clear(r, cut.clearance());
  std::vector<std::vector<Vec2>> rows;
  int last_i = INT32_MIN;
  for (std::size_t k = 0; k < plan.tool_points.pts.size(); ++k) {
    if (plan.tool_points.ij[k][0] != last_i) rows.emplace_back();
    last_i = plan.tool_points.ij[k][0];
    rows.back().push_back(plan.tool_points.pts[k]);
  }
  Chain cur;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i % 2 == 1) std::reverse(rows[i].begin(), rows[i].end());
    for (const Vec2& p : rows[i]) {
      if (!cur.pts.empty() && !clear.move_ok(cur.pts.back().p(), p)) {
        plan.path.chains.push_back(cur);
        cur = Chain{};
      }
      cur.pts.push_back({p.x(), p.y(), 0});
    }
  }
  plan.path.chains.push_back(cur);
  for (const Chain& c : plan.path.chains) plan.predrill.push_back(c.pts.front().p());
  return plan;
}
}  // namespace

class BenchPocket : public ::testing::TestWithParam<const char*> {};

TEST_P(BenchPocket, GougeFreeAndFiguresAgreeWithReplay) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + GetParam() + ".json");
  CutParams cut;
  cut.tool.diameter = 10;
  cut.stepover = 5;
  cut.depth = 5;
  cut.step_down = 2.5;
  const PlanResult plan = row_plan(pf.region, cut);
  ASSERT_EQ(plan.status, PlanStatus::Ok);
  const std::pair<const char*, bool> runs[] = {{"predrill", false}, {"helix", true}, {"ramp", true}};
  for (const auto& [entry, contour] : runs) {
    {
      MachiningOptions opt;
      opt.entry = parse_entry(entry);
      SCOPED_TRACE(std::string(GetParam()) + " " + entry);
      opt.contour = contour;
      const MachiningResult m = machine_pocket(pf.region, cut, plan, opt);
      ASSERT_EQ(m.status, PlanStatus::Ok);
      auto rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(m.program), cut.safe_z);
      millnet::testing::check_gouge(rep, to_replay(pf.region), cut.tool.diameter / 2);
      EXPECT_EQ(rep.violations, 0) << GetParam() << " " << entry << " contour " << contour << ": "
                                   << rep.first_violation;
      EXPECT_LT(rep.worst_mm, 0.01);
      // 4-decimal coordinates: ≤ ~1e-6 relative drift over thousands of segments.
      EXPECT_NEAR(m.metrics.cut_length_mm, rep.cut_length, 1e-3 + 2e-6 * rep.cut_length);
      EXPECT_NEAR(m.metrics.rapid_length_mm, rep.rapid_length, 1e-2);
      EXPECT_EQ(m.metrics.levels, 2);
      EXPECT_NEAR(rep.min_z, -5, 1e-9);
      // Every level cuts the whole path (area clearing + contour) at its Z.
      ASSERT_EQ(rep.cut_length_by_z.size(), 2u);
      for (const auto& [z, len] : rep.cut_length_by_z) EXPECT_GE(len, m.path.cut_length() - 1e-2);
      EXPECT_EQ(m.metrics.tool_points, static_cast<double>(plan.tool_points.pts.size()));
      EXPECT_GT(m.metrics.time_adjusted_min, 0);
      EXPECT_GT(m.metrics.time_constant_min, 0);
      const double chains = static_cast<double>(m.path.chains.size());
      EXPECT_EQ(m.metrics.retractions, 2 * chains - 1);
      EXPECT_EQ(m.metrics.plunges, 2 * chains);
      if (std::string(entry) == "predrill") {
        // The rows are joined with the tool down where a way through cut material reaches the next
        // (link_chains, MachiningOptions::link_walls): a hole for each chain left, no more.
        EXPECT_EQ(m.metrics.predrill_points, chains);
        EXPECT_LT(chains, static_cast<double>(plan.path.chains.size()));
      }
      EXPECT_GE(m.metrics.uncut_area_mm2, 0);
      EXPECT_LE(m.metrics.uncut_area_mm2, m.metrics.reachable_area_mm2);
      EXPECT_LE(m.metrics.reachable_area_mm2, area(pf.region) + 1e-6);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Pockets, BenchPocket, ::testing::Values("four_islands", "comb", "eight_islands"));

TEST(PocketMachining, ContourPassShrinksUncutArea) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/four_islands.json");
  CutParams cut;
  const PlanResult plan = row_plan(pf.region, cut);
  MachiningOptions opt;
  opt.link_walls = false;  // each row and loop a chain of its own
  const MachiningResult a = machine_pocket(pf.region, cut, plan, opt);
  opt.contour = true;
  const MachiningResult b = machine_pocket(pf.region, cut, plan, opt);
  opt.link_walls = true;
  const MachiningResult linked = machine_pocket(pf.region, cut, plan, opt);
  // Linked, the rows and loops join the chains before them through cut material: fewer chains, and
  // no more left uncut (the links sweep a little more).
  EXPECT_LT(linked.path.chains.size(), b.path.chains.size());
  EXPECT_LE(linked.metrics.uncut_area_mm2, b.metrics.uncut_area_mm2 + 1e-6);
  // The grid leaves scallops along the walls; the wall pass removes nearly all of them.
  EXPECT_GT(a.metrics.uncut_area_mm2, 50);
  EXPECT_LT(b.metrics.uncut_area_mm2, 0.05 * a.metrics.uncut_area_mm2);
  // One contour chain per loop of the reachable area (islands 10 mm apart merge once grown by 5).
  std::size_t loops = 0;
  for (const PolyArea& c : offset_inward(pf.region, cut.clearance() + tol::contour_margin_mm, tol::contour_chord_mm))
    loops += 1 + c.holes.size();
  EXPECT_LT(loops, 6u);
  EXPECT_EQ(b.path.chains.size(), a.path.chains.size() + loops);
  // Keys come out in the documented order; a hand-made plan has no planner figures to add.
  const auto kv = b.metrics.to_key_values();
  ASSERT_EQ(kv.size(), 16u);
  EXPECT_EQ(kv[0].first, "tool_points");
  EXPECT_EQ(kv[1].first, "tour_length_mm");
  EXPECT_EQ(kv[13].first, "levels");
  EXPECT_EQ(kv[14].first, "time_kinematic_min");
  EXPECT_EQ(kv.back().first, "max_engagement_deg");
}

TEST(PocketMachining, EmptyPlanGivesStatusNotGcode) {
  Region r{{{0, 0, 0}, {8, 0, 0}, {8, 8, 0}, {0, 8, 0}}, {}};
  CutParams cut;  // Ø10 in an 8×8 pocket
  const PlanResult plan = row_plan(r, cut);
  EXPECT_EQ(plan.status, PlanStatus::NoToolPoints);
  const MachiningResult m = machine_pocket(r, cut, plan);
  EXPECT_EQ(m.status, PlanStatus::NoToolPoints);
  EXPECT_TRUE(m.program.items.empty());
  EXPECT_FALSE(m.message.empty());
}
