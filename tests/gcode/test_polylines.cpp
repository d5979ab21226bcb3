// gcode::xy_paths: the XY polylines of cuts and rapids on a hand-built program.
#include "millnet/gcode/polylines.hpp"

#include <gtest/gtest.h>

using namespace millnet::gcode;

namespace {
Move mv(Motion m, Point3 p, std::uint8_t axes = kXYZ) {
  Move x;
  x.motion = m;
  x.to = p;
  x.feed = m == Motion::Rapid ? 0 : 500;
  x.axes = axes;
  return x;
}
using P = std::array<double, 2>;
}  // namespace

TEST(Polylines, CutsAndRapidsSplitIntoRuns) {
  Program p;
  p.items.emplace_back(mv(Motion::Rapid, {0, 0, 5}));   // start known: nothing drawn
  p.items.emplace_back(Comment{"x"});                   // not a move
  p.items.emplace_back(mv(Motion::Rapid, {10, 0, 5}));  // rapid run 1
  p.items.emplace_back(mv(Motion::Line, {10, 0, -1}));  // plunge: a cut run starts, same XY twice
  p.items.emplace_back(mv(Motion::Line, {20, 0, -1}));
  p.items.emplace_back(mv(Motion::Rapid, {20, 0, 5}));  // a lift: no XY motion, not drawn
  p.items.emplace_back(mv(Motion::Rapid, {0, 0, 5}));   // rapid run 2
  const XyPaths xy = xy_paths(p);
  ASSERT_EQ(xy.rapids.size(), 2u);
  EXPECT_EQ(xy.rapids[0], (XyPolyline{P{0, 0}, P{10, 0}}));
  EXPECT_EQ(xy.rapids[1], (XyPolyline{P{20, 0}, P{0, 0}}));
  ASSERT_EQ(xy.cuts.size(), 1u);
  EXPECT_EQ(xy.cuts[0], (XyPolyline{P{10, 0}, P{10, 0}, P{20, 0}}));
}

TEST(Polylines, NothingIsDrawnBeforeXAndYAreKnown) {
  Program p;
  p.items.emplace_back(mv(Motion::Rapid, {0, 0, 5}, kZ));  // Z only: XY unknown
  p.items.emplace_back(mv(Motion::Line, {3, 0, 5}, kX));   // X only: still unknown
  p.items.emplace_back(mv(Motion::Line, {3, 4, 5}, kY));   // Y only: a move must state both
  p.items.emplace_back(mv(Motion::Line, {6, 4, 5}));       // X and Y stated: known from here
  p.items.emplace_back(mv(Motion::Line, {6, 8, 5}));
  const XyPaths xy = xy_paths(p);
  EXPECT_TRUE(xy.rapids.empty());
  ASSERT_EQ(xy.cuts.size(), 1u);
  EXPECT_EQ(xy.cuts[0], (XyPolyline{P{6, 4}, P{6, 8}}));
}

TEST(Polylines, EmptyProgramHasNoPaths) {
  const XyPaths xy = xy_paths(Program{});
  EXPECT_TRUE(xy.cuts.empty());
  EXPECT_TRUE(xy.rapids.empty());
}
