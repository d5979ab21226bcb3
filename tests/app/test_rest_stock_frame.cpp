// The stock a rest operation reads (app::stock_of): a z-map's cells become the RestStock's nodes
// at the cells' centres, in the part frame. Until 2026-12-06 the nodes stood at the cells' lower-left
// corners: every height was read half a cell off, 0.17 mm on an 84° wall of s4 at 0.025 mm cells —
// walls facing +X/+Y read as cut, the others as uncut.
#include "finish_job.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace millnet::app {
namespace {

TEST(RestStockFromAZMap, EachCellsHeightIsAtItsCentreInThePartFrame) {
  simulate::GridSpec g;
  g.x0 = 1.0, g.y0 = -2.0, g.cell = 0.025, g.nx = 40, g.ny = 30;
  // A steep plane (slope 10 in X, 3 in Y: 84.5°) in the program frame, sampled at the centres.
  auto plane = [](double x, double y) { return -5.0 + 10 * x + 3 * y; };
  std::vector<double> h(g.cells());
  for (std::size_t i = 0; i < g.ny; ++i)
    for (std::size_t j = 0; j < g.nx; ++j) h[i * g.nx + j] = plane(g.x(j), g.y(i));
  job::Frame frame;
  frame.part_top = 20, frame.top_allowance = 1, frame.stock_top = 21;  // program Z = part z − 21
  const finish::RestStock s = stock_of(simulate::ZMap::from_heights(g, h), frame);
  for (std::size_t i = 0; i < g.ny; i += 7)
    for (std::size_t j = 0; j < g.nx; j += 5)
      EXPECT_NEAR(s.height(g.x(j), g.y(i)), h[i * g.nx + j] + 21, 1e-9) << i << " " << j;
  // Between the centres the plane itself (bilinear on a plane is exact), and a point on the plane
  // under 0.3 mm of vertical stock has 0.3·cos(slope) along its normal, less half a cell's reach.
  const double x = 1.4321, y = -1.7654;
  EXPECT_NEAR(s.height(x, y), plane(x, y) + 21, 1e-9);
  const Eigen::Vector3d n = Eigen::Vector3d(-10, -3, 1).normalized();
  const Eigen::Vector3d p(x, y, plane(x, y) + 21 - 0.3);  // the design 0.3 under the stock
  const double along = 0.3 * n.z();                       // the stock's plane from p along n
  EXPECT_NEAR(s.material(p, n), along - 0.5 * g.cell * std::hypot(n.x(), n.y()), 1e-4);
}

}  // namespace
}  // namespace millnet::app
