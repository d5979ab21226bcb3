// Tool points and Clearance against hand-computed answers (degenerate grids) and brute force.
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpoints.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace millnet::pocket;
namespace {
Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }
Loop circle(double cx, double cy, double r, bool ccw) {
  const double b = ccw ? 1 : -1;
  return {{cx + r, cy, b}, {cx - r, cy, b}};
}
GridFrame frame(double s) {
  GridFrame f;
  f.spacing = s;
  return f;
}
}  // namespace

TEST(PocketToolPoints, TangentPointsAreKept) {
  // Square 0..20, clearance 5: x, y ∈ {5, 10, 15}; the outer ring lies exactly at clearance.
  const Region r{rect(0, 0, 20, 20), {}};
  EXPECT_EQ(make_tool_points(r, frame(5), 5).pts.size(), 9u);
  EXPECT_EQ(make_tool_points(r, frame(5), 5.001).pts.size(), 1u);  // only (10, 10)
}

TEST(PocketToolPoints, GridThroughVerticesAndAlongEdges) {
  // Diamond |x| + |y| ≤ 10: grid lines run through all four vertices.
  const Region dia{{{0, -10, 0}, {10, 0, 0}, {0, 10, 0}, {-10, 0, 0}}, {}};
  EXPECT_EQ(make_tool_points(dia, frame(5), 0).pts.size(), 13u);  // points on the boundary count
  EXPECT_EQ(make_tool_points(dia, frame(5), 1).pts.size(), 5u);   // |x|+|y| ≤ 10 − √2
  // Horizontal edges on grid rows: rectangle 0..30 × 0..10, clearance 2.5, spacing 2.5.
  const ToolPoints tp = make_tool_points(Region{rect(0, 0, 30, 10), {}}, frame(2.5), 2.5);
  EXPECT_EQ(tp.pts.size(), 33u);  // y ∈ {2.5, 5, 7.5} × x ∈ {2.5 … 27.5}
  // Order: by row, then column; ij consistent with frame.at.
  for (std::size_t k = 0; k < tp.pts.size(); ++k) {
    EXPECT_NEAR((tp.frame.at(tp.ij[k][0], tp.ij[k][1]) - tp.pts[k]).norm(), 0, 1e-12);
    if (k > 0) {
      EXPECT_TRUE(tp.ij[k - 1] < tp.ij[k]);
    }
  }
}

TEST(PocketToolPoints, ArcsExact) {
  // Circle r = 10, clearance 5: |p| ≤ 5 → (0,0), (±5,0), (0,±5); (±5,±5) has |p| = 7.07.
  EXPECT_EQ(make_tool_points(Region{circle(0, 0, 10, true), {}}, frame(5), 5).pts.size(), 5u);
  // An island of radius 1 at the centre leaves no room at all: empty, no crash.
  const Region ring{circle(0, 0, 10, true), {circle(0, 0, 1, false)}};
  EXPECT_TRUE(make_tool_points(ring, frame(5), 5).pts.empty());
  // Clearance 2: 2 + 1 ≤ |p| ≤ 8 → (±5,0), (0,±5), (±5,±5) = 8 points (the centre is out).
  EXPECT_EQ(make_tool_points(ring, frame(5), 2).pts.size(), 8u);
  // A grid rotated by 45° about the centre: the 5 points rotate with it and stay within |p| ≤ 5.
  GridFrame f = frame(5);
  f.angle_deg = 45;
  EXPECT_EQ(make_tool_points(Region{circle(0, 0, 10, true), {}}, f, 5).pts.size(), 5u);
}

TEST(PocketClearance, MatchesBruteForce) {
  // Seed 11: random points and moves in a pocket with arcs, a long diagonal wall and islands;
  // oracle = all walls. Clearances from none to more than the islands' size: the bucket grid's cell
  // follows the clearance (a wall is registered only in the cells it passes through), so each
  // clearance exercises another grid.
  const Region r{{{0, 0, 0}, {100, 0, 0.4}, {100, 60, 0}, {40, 75, 0}, {0, 60, -0.2}},
                 {circle(30, 30, 8, false), rect(60, 20, 75, 40)}};
  std::vector<Segment> walls = segments(r.boundary);
  for (const Loop& l : r.islands)
    for (const Segment& s : segments(l)) walls.push_back(s);
  for (const double cl : {0.0, 0.4, 5.0, 12.0}) {
    SCOPED_TRACE("clearance " + std::to_string(cl));
    const Clearance c(r, cl);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> X(-10, 110), Y(-10, 85), D(-8, 8);
    int ok_count = 0, move_ok_count = 0;
    for (int t = 0; t < 3000; ++t) {
      const Vec2 p(X(rng), Y(rng));
      double best = 1e300;
      for (const Segment& s : walls) best = std::min(best, distance(s, p));
      ASSERT_NEAR(c.wall_distance(p), best, 1e-12);
      const bool ok = best >= cl - 1e-6 && inside(r, p);
      ASSERT_EQ(c.point_ok(p), ok) << p.transpose();
      ok_count += ok;
      const Vec2 q = p + Vec2(D(rng), D(rng));
      double mbest = 1e300;
      for (const Segment& s : walls) mbest = std::min(mbest, distance(s, p, q));
      const bool mok = ok && mbest >= cl - 1e-6 && inside(r, q);
      ASSERT_EQ(c.move_ok(p, q), mok) << p.transpose() << " -> " << q.transpose();
      move_ok_count += mok;
    }
    EXPECT_GT(ok_count, 100);  // the test exercises both answers
    EXPECT_GT(move_ok_count, 50);
  }
}
