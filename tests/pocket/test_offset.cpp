// Clipper offsets against analytic areas.
#include "offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace millnet::pocket;
namespace {
constexpr double kPi = std::numbers::pi;
Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }
}  // namespace

TEST(PocketOffset, RectangleShrinksExactlyAndOpeningRoundsCorners) {
  const Region r{rect(0, 0, 40, 30), {}};
  const auto in = offset_inward(r, 5, 1e-4);
  ASSERT_EQ(in.size(), 1u);
  EXPECT_TRUE(in[0].holes.empty());
  // Eroding a convex rectangle keeps sharp corners: (w − 2d)(h − 2d).
  EXPECT_NEAR(area(in), 30.0 * 20.0, 1e-3);
  // Growing back by d rounds the corners: w·h − (4 − π)d² (the tool-reachable area). Inscribed
  // chords (error 1e-4) lose ≈ (2/3)·1e-4·(π/2·5) ≈ 5e-4 mm² per corner.
  EXPECT_NEAR(area(offset_areas(in, 5, 1e-4)), 40.0 * 30.0 - (4 - kPi) * 25, 0.004);
}

TEST(PocketOffset, IslandsGrowWithRoundCorners) {
  const Region r{rect(0, 0, 100, 100), {rect(40, 40, 50, 50)}};  // island orientation is normalised by Clipper
  const auto in = offset_inward(r, 3, 1e-4);
  ASSERT_EQ(in.size(), 1u);
  ASSERT_EQ(in[0].holes.size(), 1u);
  const double hole = 100 + 4 * 10 * 3 + kPi * 9;
  EXPECT_NEAR(area(in), 94.0 * 94.0 - hole, 0.004);
}

TEST(PocketOffset, NarrowCorridorSplitsComponents) {
  // Two 20×20 rooms joined by a corridor 4 wide: offset by 3 leaves two separate components.
  const Region r{{{0, 0, 0},
                  {20, 0, 0},
                  {20, 8, 0},
                  {30, 8, 0},
                  {30, 0, 0},
                  {50, 0, 0},
                  {50, 20, 0},
                  {30, 20, 0},
                  {30, 12, 0},
                  {20, 12, 0},
                  {20, 20, 0},
                  {0, 20, 0}},
                 {}};
  const auto in = offset_inward(r, 3);
  EXPECT_EQ(in.size(), 2u);
  // Each room keeps its 14×14 core plus a sliver at the corridor mouth (bounded by the 3×4 strip
  // the mouth frees), where the reflex corners' offsets are arcs.
  EXPECT_GT(area(in), 2 * 14.0 * 14.0 + 0.5);
  EXPECT_LT(area(in), 2 * 14.0 * 14.0 + 2 * 12.0);
  EXPECT_EQ(offset_inward(r, 1.9).size(), 1u);
  EXPECT_TRUE(offset_inward(r, 11).empty());
}

TEST(PocketOffset, SweptAreaAndDifference) {
  // A capsule: length 10, radius 2 → 40 + 4π; minus a 4×4 square in its middle.
  const auto cap = swept_area({{Vec2(0, 0), Vec2(10, 0)}}, 2, 1e-4);
  EXPECT_NEAR(area(cap), 40 + 4 * kPi, 1e-3);
  PolyArea sq;
  sq.outer = {Vec2(3, -2), Vec2(7, -2), Vec2(7, 2), Vec2(3, 2)};
  EXPECT_NEAR(area(difference(cap, {sq})), 40 + 4 * kPi - 16, 1e-3);
  // A single point sweeps a disk.
  EXPECT_NEAR(area(swept_area({{Vec2(1, 1)}}, 3, 1e-4)), 9 * kPi, 2e-3);
}
