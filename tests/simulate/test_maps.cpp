// Per-cell maps: block means on small grids computed by hand, and the design surface from a height field.
#include "millnet/simulate/maps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace millnet::simulate;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

TEST(Maps, BlockMeansOfA3x3GridInto2x2Blocks) {
  // nx = ny = 3, max 2 cells per side ⇒ k = 2: blocks {0,1}×{0,1}, {0,1}×{2}, {2}×{0,1}, {2}×{2}.
  const std::vector<double> v{1, 2, 3,   // row 0 (y = 0)
                              4, 5, 6,   // row 1
                              7, 8, 9};  // row 2
  const Eigen::MatrixXd m = block_means(v, 3, 3, 2, -1.0);
  ASSERT_EQ(m.rows(), 2);
  ASSERT_EQ(m.cols(), 2);
  EXPECT_DOUBLE_EQ(m(0, 0), (1 + 2 + 4 + 5) / 4.0);
  EXPECT_DOUBLE_EQ(m(0, 1), (3 + 6) / 2.0);
  EXPECT_DOUBLE_EQ(m(1, 0), (7 + 8) / 2.0);
  EXPECT_DOUBLE_EQ(m(1, 1), 9.0);
}

TEST(Maps, BlockMeansSkipNonFiniteCellsAndFillEmptyBlocks) {
  // 4 × 2 (nx = 4, ny = 2), max 2 ⇒ k = 2: two blocks side by side.
  const std::vector<double> v{1, kNaN, kNaN, kNaN, 3, kNaN, kNaN, std::numeric_limits<double>::infinity()};
  const Eigen::MatrixXd m = block_means(v, 4, 2, 2, -7.0);
  ASSERT_EQ(m.rows(), 1);
  ASSERT_EQ(m.cols(), 2);
  EXPECT_DOUBLE_EQ(m(0, 0), 2.0);   // (1 + 3) / 2
  EXPECT_DOUBLE_EQ(m(0, 1), -7.0);  // nothing finite
}

TEST(Maps, BlockMeansKeepSmallGridsAsTheyAre) {
  const std::vector<double> v{1, 2, 3, 4, 5, 6};  // nx = 3, ny = 2
  const Eigen::MatrixXd m = block_means(v, 3, 2, 500, 0.0);
  ASSERT_EQ(m.rows(), 2);
  ASSERT_EQ(m.cols(), 3);
  EXPECT_DOUBLE_EQ(m(1, 0), 4.0);
  EXPECT_DOUBLE_EQ(m(0, 2), 3.0);
}

TEST(Maps, DesignHeightsShiftHitsAndLeaveTheRestNaN) {
  millnet::ingest::HeightField hf;
  hf.nx = 2;
  hf.ny = 2;
  hf.z = {1.0, 2.0, 0.5, 4.0};
  hf.hit = {1, 0, 1, 1};
  const std::vector<double> d = design_heights(hf, -5.0);
  ASSERT_EQ(d.size(), 4u);
  EXPECT_DOUBLE_EQ(d[0], -4.0);
  EXPECT_TRUE(std::isnan(d[1]));
  EXPECT_DOUBLE_EQ(d[2], -4.5);
  EXPECT_DOUBLE_EQ(d[3], -1.0);
}
