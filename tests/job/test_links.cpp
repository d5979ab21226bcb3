// job/links: a program's rapids lifted over the stock that is left. A hand-made stock (a floor at
// Z −20 with a 10 mm wide ridge up to Z −5) and rapids that cross the ridge, pass beside it and
// come down onto it: each rewritten as a CAM engineer would (over the ridge + the clearance, down to
// the clearance, the rest at the plunge feed), checked by machining both programs on the z-map
// (simulate::machine counts the rapids that remove material).
#include "millnet/job/links.hpp"

#include "millnet/simulate/zmap.hpp"
#include "testing/moves.hpp"

#include <gtest/gtest.h>

#include <variant>

using namespace millnet;
using gcode::Motion;

namespace {

simulate::ZMap ridge_stock() {
  simulate::GridSpec g;
  g.x0 = 0, g.y0 = 0, g.cell = 0.1, g.nx = 400, g.ny = 400;
  simulate::ZMap z = simulate::ZMap::flat(g, -20);
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix)
      if (g.x(ix) > 10 && g.x(ix) < 20) z.heights()[iy * g.nx + ix] = -5;
  return z;
}

std::vector<gcode::Move> moves(const gcode::Program& p) {
  std::vector<gcode::Move> out;
  for (const auto& it : p.items)
    if (const auto* m = std::get_if<gcode::Move>(&it)) out.push_back(*m);
  return out;
}

}  // namespace

TEST(JobLinks, RapidsClearTheStockLeftAndFinishTheirApproachAtThePlungeFeed) {
  const tooling::Cutter ball = tooling::Cutter::ball(6);
  gcode::Program p;
  p.items = {
      millnet::testing::move(Motion::Rapid, {5, 5, 5}, 0, gcode::kXYZ),
      millnet::testing::move(Motion::Rapid, {5, 5, -10}, 0, gcode::kZ),                // down beside the ridge: kept
      millnet::testing::move(Motion::Rapid, {30, 5, -10}, 0, gcode::kX | gcode::kY),   // through the ridge: raised
      millnet::testing::move(Motion::Rapid, {24, 30, -10}, 0, gcode::kX | gcode::kY),  // 4 mm beside it (r 3): kept
      millnet::testing::move(Motion::Rapid, {15, 30, -12}, 0, gcode::kXYZ),            // onto the ridge: raised, fed
      millnet::testing::move(Motion::Line, {15, 35, -12}, 1000, gcode::kY),            // a cut: kept
      millnet::testing::move(Motion::Rapid, {15, 35, 5}, 0, gcode::kZ)};               // up: kept
  job::LinkChanges ch;
  const gcode::Program q = job::clear_rapids(p, ridge_stock(), ball, 1.0, 300, &ch);
  EXPECT_EQ(ch.raised, 2u);
  EXPECT_EQ(ch.fed, 1u);
  const std::vector<gcode::Move> m = moves(q);
  // Hand-written: the ridge's top −5 + clearance 1 = −4 is the height of both crossings.
  const std::vector<std::pair<Motion, gcode::Point3>> want{
      {Motion::Rapid, {5, 5, 5}},    {Motion::Rapid, {5, 5, -10}},  {Motion::Rapid, {5, 5, -4}},
      {Motion::Rapid, {30, 5, -4}},  {Motion::Rapid, {30, 5, -10}}, {Motion::Rapid, {24, 30, -10}},
      {Motion::Rapid, {24, 30, -4}}, {Motion::Rapid, {15, 30, -4}}, {Motion::Line, {15, 30, -12}},
      {Motion::Line, {15, 35, -12}}, {Motion::Rapid, {15, 35, 5}}};
  ASSERT_EQ(m.size(), want.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    SCOPED_TRACE("move " + std::to_string(i));
    EXPECT_EQ(m[i].motion, want[i].first);
    for (int a = 0; a < 3; ++a)
      EXPECT_DOUBLE_EQ(m[i].to[static_cast<std::size_t>(a)], want[i].second[static_cast<std::size_t>(a)]);
  }
  EXPECT_DOUBLE_EQ(m[8].feed, 300);

  // Machined: the original's rapids cut the ridge, the rewritten program's never do.
  simulate::ZMap a = ridge_stock(), b = ridge_stock();
  EXPECT_EQ(simulate::machine(a, p, ball).cutting_rapids.size(), 2u);
  const simulate::SweepResult sb = simulate::machine(b, q, ball);
  EXPECT_TRUE(sb.cutting_rapids.empty());
  EXPECT_NEAR(sb.max_cut_mm[simulate::kLineKind], 7.0, 0.01) << "the plunge and the cut do the cutting";
}

TEST(JobLinks, AProgramThatClearsTheStockIsKeptAsItIs) {
  gcode::Program p;
  p.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}, 0, gcode::kZ),
             millnet::testing::move(Motion::Rapid, {5, 5, 5}, 0, gcode::kX | gcode::kY),
             millnet::testing::move(Motion::Rapid, {35, 35, -3}, 0, gcode::kXYZ),
             millnet::testing::move(Motion::Line, {35, 35, -19}, 300, gcode::kZ)};
  job::LinkChanges ch;
  const gcode::Program q = job::clear_rapids(p, ridge_stock(), tooling::Cutter::flat(10), 1.0, 300, &ch);
  EXPECT_EQ(ch.raised + ch.fed, 0u);
  ASSERT_EQ(moves(q).size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(moves(q)[i].to, moves(p)[i].to);
}
