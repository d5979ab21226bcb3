// A rest piece cut where it cuts, from the top down (detail::stepped_runs, issue 41): the
// stretches and their lifts by hand, on a made-up stock depth along a straight piece.
#include "rest_internal.hpp"

#include "millnet/finish/rest.hpp"
#include "millnet/tooling/cutter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

using millnet::finish::Pass;
using millnet::finish::detail::stepped_runs;

namespace {
/// A straight piece from (0, 0, z) to (10, 0, z) in vertices 1 mm apart.
Pass straight(double z) {
  Pass p;
  for (int i = 0; i <= 10; ++i) p.points.emplace_back(i, 0, z);
  return p;
}

/// How deep the tool cuts at x along the piece (tip at the piece's own height, 0): 2.5 mm over
/// [2, 4], 0.5 over [6, 7], 0.003 (a scallop's worth) over [8, 9], nothing elsewhere; above the
/// piece it cuts that less the tip's lift.
double depth_at(double x, double z) {
  const double h = x >= 2 && x <= 4 ? 2.5 : x >= 6 && x <= 7 ? 0.5 : x >= 8 && x <= 9 ? 0.003 : 0.0;
  return std::max(0.0, h - z);
}
}  // namespace

// Steps of 1 mm, cuts under 0.005 mm left out, run on by 0.1 mm, sampled every 0.05 mm: two
// raised copies over [2, 4] alone (at +2 and +1: the 2.5 mm rest is taken 0.5, 1, 1 from the top),
// then the piece itself over [2, 4] and [6, 7] (each run on by 0.1), not over the 0.003 mm scallop.
TEST(RestRuns, APieceCutsFromTheTopDownAndOnlyWhereItCuts) {
  const Pass piece = straight(0);
  int raised = -1;
  const auto runs = stepped_runs(
      piece, [](double x, double, double z) { return depth_at(x, z); }, 1.0, 0.005, 0.05, 0.1, 0.0, &raised);
  ASSERT_EQ(runs.size(), 4U);
  EXPECT_EQ(raised, 2);
  const double lift[] = {2, 1, 0, 0}, from[] = {1.9, 1.9, 1.9, 5.9}, to[] = {4.1, 4.1, 4.1, 7.1};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    SCOPED_TRACE(k);
    const auto& p = runs[k].points;
    EXPECT_FALSE(runs[k].closed);
    EXPECT_NEAR(p.front().x(), from[k], 1e-9);
    EXPECT_NEAR(p.back().x(), to[k], 1e-9);
    for (const auto& q : p) {
      EXPECT_NEAR(q.z(), lift[k], 1e-12);
      EXPECT_EQ(q.y(), 0.0);
    }
    // The piece's own vertices inside the stretch are kept, in order: 2, 3, 4 (or 6, 7).
    EXPECT_EQ(p.size(), k < 3 ? 5U : 4U);
    for (std::size_t i = 1; i + 1 < p.size(); ++i) EXPECT_EQ(p[i].x(), std::round(p[i].x()));
  }
}

// A piece the stock stands over all along is itself, unchanged (a loop stays a loop); one over
// stock no deeper than the scallop is left out; no stepping without a step (flutes unstated).
TEST(RestRuns, AWholePieceStaysAsPlannedAndOneInTheAirIsLeftOut) {
  Pass loop;
  for (int i = 0; i <= 8; ++i)
    loop.points.emplace_back(std::cos(i * std::numbers::pi / 4), std::sin(i * std::numbers::pi / 4), 0.0);
  loop.closed = true;
  const auto whole = stepped_runs(
      loop, [](double, double, double z) { return 0.3 - z; }, 1.0, 0.005, 0.05, 0.1);
  ASSERT_EQ(whole.size(), 1U);
  EXPECT_TRUE(whole[0].closed);
  EXPECT_EQ(whole[0].points, loop.points);
  EXPECT_TRUE(stepped_runs(
                  straight(0), [](double, double, double) { return 0.004; }, 1.0, 0.005, 0.05, 0.1)
                  .empty());
  const auto flat = stepped_runs(
      straight(0), [](double x, double, double z) { return depth_at(x, z); }, 0.0, 0.005, 0.05, 0.1);
  ASSERT_EQ(flat.size(), 2U);  // [1.9, 4.1] and [5.9, 7.1] at the piece's height, however deep
  EXPECT_NEAR(flat[0].points.front().z(), 0.0, 1e-12);
}

// Stretches no more than `bridge` apart are cut as one (the tool stays on the pass across the gap
// instead of leaving it for a link): [1.9, 4.1] and [5.9, 7.1] are 1.8 mm apart.
TEST(RestRuns, StretchesABridgeApartAreCutAsOne) {
  const auto depth = [](double x, double, double z) { return depth_at(x, z); };
  const auto apart = stepped_runs(straight(0), depth, 0.0, 0.005, 0.05, 0.1, 1.7);
  ASSERT_EQ(apart.size(), 2U);
  const auto joined = stepped_runs(straight(0), depth, 0.0, 0.005, 0.05, 0.1, 1.9);
  ASSERT_EQ(joined.size(), 1U);
  EXPECT_NEAR(joined[0].points.front().x(), 1.9, 1e-9);
  EXPECT_NEAR(joined[0].points.back().x(), 7.1, 1e-9);
  EXPECT_EQ(joined[0].points.size(), 8U);  // 1.9, the vertices 2 … 7, 7.1
}

// With the piece's own sweep (RestStock::removal_behind) a patch ends where the tool's front leaves
// it: a Ø1 ball at tip 0 along y = 1 over a block 0.1 mm tall on 1 ≤ x ≤ 2 (cells of 0.025). Judged
// on the stock as it was, the ball's back still meets the block until its surface clears 0.1 mm,
// √(2·0.5·0.1 − 0.1²) = 0.3 past x = 2; behind its own samples (0.125 apart, each leaving cusps of
// 0.5 − √(0.25 − 0.0625²) = 0.0039 mm < the 0.005 mm left out) it takes nothing past x = 2 + a sample.
TEST(RestRuns, APatchEndsWhereTheToolsFrontLeavesIt) {
  millnet::finish::RestStock st;
  st.cell = 0.025, st.x0 = 0, st.y0 = 0, st.nx = 161, st.ny = 81;
  st.z.assign(161 * 81, 0.0);
  for (int i = 0; i < 81; ++i)
    for (int j = 40; j <= 80; ++j) st.z[static_cast<std::size_t>(i * 161 + j)] = 0.1;
  const auto ball = millnet::tooling::Cutter::ball(1);
  Pass piece;
  piece.points = {{0.2, 1, 0}, {3.8, 1, 0}};
  auto removal = [&](double x, double y, double z) { return st.removal(ball, x, y, z); };
  const auto plain = stepped_runs(piece, removal, 0.0, 0.005, 0.125, 0.0625, 0.5);
  ASSERT_EQ(plain.size(), 1U);
  EXPECT_NEAR(plain.front().points.front().x(), 1 - 0.3, 0.125 + 0.0625 + 1e-9);
  EXPECT_GT(plain.front().points.back().x(), 2.2);
  const auto own = stepped_runs(piece, removal, 0.0, 0.005, 0.125, 0.0625, 0.5, nullptr,
                                [&](const Eigen::Vector3d& p, const Eigen::Vector3d* before, std::size_t n) {
                                  return st.removal_behind(ball, p, before, n);
                                });
  ASSERT_EQ(own.size(), 1U);
  EXPECT_NEAR(own.front().points.front().x(), plain.front().points.front().x(), 1e-9);  // it meets it alike
  EXPECT_LT(own.front().points.back().x(), 2 + 0.125 + 0.0625 + 1e-9);
  EXPECT_GE(own.front().points.back().x(), 2 - 0.0625);
}

// The piece itself runs where it takes more than the scallop normal to the surface, its raised
// copies where the flutes meet more than a step above it: over [2, 4] a wall's tall, thin sliver
// (2.5 mm high, 0.003 mm across: the cusps a bigger ball left, in spec) is stepped down by the
// copies at +2 and +1 but not cut again by the piece; over [6, 7] 0.02 mm of floor rest is.
TEST(RestRuns, ThePieceRunsWhereItTakesMoreThanTheScallopAcrossTheSurface) {
  const auto removal = [](double x, double, double z) {
    if (x >= 2 && x <= 4) return millnet::finish::Removal(std::max(0.0, 2.5 - z), 0.003);
    if (x >= 6 && x <= 7) return millnet::finish::Removal(std::max(0.0, 0.02 - z));
    return millnet::finish::Removal();
  };
  int raised = -1;
  const auto runs = stepped_runs(straight(0), removal, 1.0, 0.005, 0.05, 0.0, 0.0, &raised);
  ASSERT_EQ(runs.size(), 3U);
  EXPECT_EQ(raised, 2);
  const double lift[] = {2, 1, 0}, from[] = {2, 2, 6}, to[] = {4, 4, 7};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_NEAR(runs[k].points.front().x(), from[k], 1e-9);
    EXPECT_NEAR(runs[k].points.back().x(), to[k], 1e-9);
    EXPECT_NEAR(runs[k].points.front().z(), lift[k], 1e-12);
  }
}

// The pass left nearest a point, turned to begin there: an open pass from either end, a loop from
// any vertex (its last repeating its first); those taken are not offered again.
TEST(RestRuns, TheNearestPassIsTakenTurnedToBeginNearest) {
  std::vector<Pass> passes(3);
  passes[0].points = {{0, 0, 0}, {1, 0, 0}};
  passes[1].points = {{5, 0, 0}, {3, 0, 0}};
  passes[2].points = {{0, 4, 0}, {1, 4, 0}, {1, 5, 0}, {0, 5, 0}, {0, 4, 0}};
  passes[2].closed = true;
  std::vector<std::uint8_t> done(3, 0);
  std::size_t index = 9;
  const Pass a = millnet::finish::detail::take_nearest(passes, done, Eigen::Vector3d(2.9, 0.2, 0), &index);
  EXPECT_EQ(index, 1U);
  EXPECT_EQ(a.points.front(), Eigen::Vector3d(3, 0, 0));  // backwards
  EXPECT_EQ(a.points.back(), Eigen::Vector3d(5, 0, 0));
  const Pass b = millnet::finish::detail::take_nearest(passes, done, Eigen::Vector3d(1.1, 5.2, 0), &index);
  EXPECT_EQ(index, 2U);
  ASSERT_EQ(b.points.size(), 5U);
  EXPECT_EQ(b.points.front(), Eigen::Vector3d(1, 5, 0));  // from its vertex nearest, closed again
  EXPECT_EQ(b.points.back(), Eigen::Vector3d(1, 5, 0));
  EXPECT_EQ(b.points[1], Eigen::Vector3d(0, 5, 0));
  const Pass c = millnet::finish::detail::take_nearest(passes, done, Eigen::Vector3d(9, 9, 0), &index);
  EXPECT_EQ(index, 0U);  // the one left, however far
  EXPECT_EQ(c.points.front(), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(done, std::vector<std::uint8_t>(3, 1));
}
