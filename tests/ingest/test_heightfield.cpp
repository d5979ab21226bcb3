// Height sampling: analytic surfaces, a brute-force per-ray oracle, shared edges, thread counts.
#include "ingest/builders.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace millnet::ingest;
using namespace millnet::testing_ingest;

namespace {

// Independent oracle: a vertical ray through (x, y) against every triangle (barycentric in
// doubles, no shared code with the rasterizer), highest hit. O(#F) per point.
bool ray_top(const Mesh& m, double x, double y, double& z) {
  bool any = false;
  z = -std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
    const Eigen::Vector3d a = m.V.row(m.F(t, 0)), b = m.V.row(m.F(t, 1)), c = m.V.row(m.F(t, 2));
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(det) < 1e-12) continue;
    const double l1 = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const double l2 = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    const double l0 = 1 - l1 - l2;
    if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
    z = std::max(z, l0 * a.z() + l1 * b.z() + l2 * c.z());
    any = true;
  }
  return any;
}

}  // namespace

TEST(HeightField, TiltedPlaneExactAndGridBilinear) {
  // z = 2 + 0.1x + 0.05y over 100×60 mm from two triangles: every raster point is hit and exact.
  const Mesh m = surface([](double x, double y) { return 2 + 0.1 * x + 0.05 * y; }, 0, 100, 0, 60, 1, 1);
  const HeightField f = rasterize_top(m, 1.0);
  ASSERT_EQ(f.nx, 101);
  ASSERT_EQ(f.ny, 61);
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      ASSERT_TRUE(f.hit[static_cast<std::size_t>(i * f.nx + j)]) << i << "," << j;
      ASSERT_NEAR(f.at(i, j), 2 + 0.1 * j + 0.05 * i, 1e-12);
    }
  // 15×15 grid relative to the lowest point (z = 2): bilinear reproduces a plane exactly.
  const Grid g = sample_grid(m, 1.0, 15);
  EXPECT_DOUBLE_EQ(g.footprint_x, 100);
  EXPECT_DOUBLE_EQ(g.footprint_y, 60);
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c) EXPECT_NEAR(g.h(r, c), 0.1 * (100.0 * c / 14) + 0.05 * (60.0 * r / 14), 1e-11);
}

TEST(HeightField, RampSolidNonSquareFootprintShrinksStep) {
  // Wedge solid 50.5 × 20 mm, top z = 10 + 0.3x, flat base at 0: 50.5/1 → 51 steps of 0.990… mm.
  const Mesh m = solid([](double x, double) { return 10 + 0.3 * x; }, 0, 50.5, 0, 20, 5, 2);
  const HeightField f = rasterize_top(m, 1.0);
  EXPECT_EQ(f.nx, 52);
  EXPECT_EQ(f.ny, 21);
  EXPECT_NEAR(f.step_x, 50.5 / 51, 1e-15);
  EXPECT_DOUBLE_EQ(f.z_min, 0);
  const Grid g = resample(f, 15);
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c) EXPECT_NEAR(g.h(r, c), 10 + 0.3 * (50.5 * c / 14), 1e-10);
}

TEST(HeightField, HemisphereWithinInterpolationError) {
  // Dome z = sqrt(R² − r²) (0 outside) on a 0.25 mm vertex grid over an 84 mm square; raster 0.7 mm
  // is not aligned with the vertices. The piecewise-linear surface of a concave function lies below
  // it, by at most h²·|f''|/2 ≈ 0.03 mm where r ≤ 0.9R.
  const double R = 30;
  auto dome = [R](double x, double y) { return std::sqrt(std::max(0.0, R * R - x * x - y * y)); };
  const Mesh m = surface(dome, -42, 42, -42, 42, 336, 336);
  const HeightField f = rasterize_top(m, 0.7);
  int checked = 0;
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      const double x = f.x0 + j * f.step_x, y = f.y0 + i * f.step_y;
      ASSERT_TRUE(f.hit[static_cast<std::size_t>(i * f.nx + j)]);
      if (std::hypot(x, y) > 0.9 * R) continue;
      EXPECT_LE(f.at(i, j), dome(x, y) + 1e-9);
      EXPECT_GE(f.at(i, j), dome(x, y) - 0.05);
      ++checked;
    }
  EXPECT_GT(checked, 4000);
  // Raster 1 mm over 84 mm: the 15×15 grid lines fall on every 6th raster point (weights 0/1).
  const Grid g = sample_grid(m, 1.0, 15);
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c) {
      const double x = -42 + 6.0 * c, y = -42 + 6.0 * r;
      const double tolerance = std::hypot(x, y) <= 0.9 * R ? 0.05 : (std::hypot(x, y) >= R + 0.5 ? 1e-12 : 2.5);
      EXPECT_NEAR(g.h(r, c), dome(x, y), tolerance) << r << "," << c;
    }
}

TEST(HeightField, BoxWithStepWallTopsIncluded) {
  // Plate 50×40×5 plus a block [20,35]×[10,30] up to z = 15 (two overlapping closed boxes).
  const Mesh m = append(box(0, 0, 0, 50, 40, 5), box(20, 10, 5, 35, 30, 15));
  const HeightField f = rasterize_top(m, 1.0);
  ASSERT_EQ(f.nx, 51);
  ASSERT_EQ(f.ny, 41);
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      // Points on the block's walls (j = 20, 35; i = 10, 30) take the wall's top.
      const bool on_block = j >= 20 && j <= 35 && i >= 10 && i <= 30;
      ASSERT_EQ(f.at(i, j), on_block ? 15.0 : 5.0) << i << "," << j;
    }
  const Grid g = resample(f, 11);  // grid lines every 5 mm, every 4 mm
  EXPECT_DOUBLE_EQ(g.h(0, 0), 5);
  EXPECT_DOUBLE_EQ(g.h(5, 5), 15);  // (25, 20)
  EXPECT_DOUBLE_EQ(g.h(5, 4), 15);  // (20, 20): on the wall
  EXPECT_DOUBLE_EQ(g.h(5, 3), 5);   // (15, 20)
}

TEST(HeightField, VerticalWallAloneGivesItsTopEdge) {
  // A lone vertical rectangle in the plane y = 2 from z = 0 to z = 3 + 0.5x: raster points on
  // y = 2 get the wall's top, the others are unhit (z_min).
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 2, 0, 10, 2, 0, 10, 2, 8, 0, 2, 3;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  const HeightField f = rasterize_top(m, 0.0, 0.0, 1.0, 11, 5);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 11; ++j) {
      const bool on = i == 2;
      EXPECT_EQ(f.hit[static_cast<std::size_t>(i * 11 + j)], on ? 1 : 0);
      EXPECT_NEAR(f.at(i, j), on ? 3 + 0.5 * j : 0.0, 1e-12) << i << "," << j;
    }
}

TEST(HeightField, SharedEdgesAndVerticesAreAlwaysHit) {
  // Jittered heights on a vertex grid whose vertices and diagonal edges pass exactly through
  // raster points (0.5 mm raster over 1 mm cells, also offset by 1/3 mm so (x−x0)/step rounds):
  // every raster point must be hit and match the oracle.
  std::mt19937 rng(12345);
  std::printf("seed 12345\n");
  std::uniform_real_distribution<double> u(0, 5);
  std::vector<double> heights(21 * 21);
  for (double& h : heights) h = u(rng);
  for (double offset : {0.0, 1.0 / 3.0, 1e6 + 0.1}) {
    Mesh m = surface([](double, double) { return 0.0; }, offset, offset + 20, offset, offset + 20, 20, 20);
    for (Eigen::Index k = 0; k < m.V.rows(); ++k) m.V(k, 2) = heights[static_cast<std::size_t>(k)];
    const HeightField f = rasterize_top(m, 0.5);
    ASSERT_EQ(f.nx, 41);
    for (int i = 0; i < f.ny; ++i)
      for (int j = 0; j < f.nx; ++j) {
        ASSERT_TRUE(f.hit[static_cast<std::size_t>(i * f.nx + j)]) << "offset " << offset << " at " << i << "," << j;
        double z;
        ASSERT_TRUE(ray_top(m, f.x0 + j * f.step_x, f.y0 + i * f.step_y, z));
        ASSERT_NEAR(f.at(i, j), z, 1e-9);
      }
  }
}

TEST(HeightField, MatchesBruteForceRayOracleOnRandomSoups) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::printf("seed %u\n", seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(0, 20), zz(-5, 5), small(-3, 3);
    Mesh m;
    const int n = 300;
    m.V.resize(3 * n, 3);
    m.F.resize(n, 3);
    for (int t = 0; t < n; ++t) {
      const double cx = xy(rng), cy = xy(rng);
      for (int k = 0; k < 3; ++k) m.V.row(3 * t + k) << cx + small(rng), cy + small(rng), zz(rng);
      m.F.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    }
    const HeightField f = rasterize_top(m, 0.37);
    int hits = 0;
    for (int i = 0; i < f.ny; ++i)
      for (int j = 0; j < f.nx; ++j) {
        double z;
        const bool any = ray_top(m, f.x0 + j * f.step_x, f.y0 + i * f.step_y, z);
        ASSERT_EQ(f.hit[static_cast<std::size_t>(i * f.nx + j)] != 0, any) << "seed " << seed << " " << i << "," << j;
        if (any) {
          ASSERT_NEAR(f.at(i, j), z, 1e-9);
          ++hits;
        } else {
          ASSERT_EQ(f.at(i, j), f.z_min);
        }
      }
    EXPECT_GT(hits, 1000);
  }
}

TEST(HeightField, ThreadCountInvariantBitwise) {
  const Mesh m = surface([](double x, double y) { return 3 * std::sin(0.3 * x) * std::cos(0.2 * y) + 0.01 * x * y; }, 0,
                         97.3, 0, 61.1, 250, 200);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const HeightField a = rasterize_top(m, 0.13);
  omp_set_num_threads(2);
  const HeightField b = rasterize_top(m, 0.13);
  omp_set_num_threads(saved);
  ASSERT_EQ(a.z.size(), b.z.size());
  EXPECT_EQ(std::memcmp(a.z.data(), b.z.data(), a.z.size() * sizeof(double)), 0);
  EXPECT_EQ(a.hit, b.hit);
}

TEST(HeightField, ExplicitRectangleLargerThanPartFillsZMin) {
  const Mesh m = box(2, 2, 1, 4, 4, 6);
  const HeightField f = rasterize_top(m, 0, 0, 1, 7, 7);
  EXPECT_EQ(f.z_min, 1);
  EXPECT_EQ(f.at(0, 0), 1);
  EXPECT_EQ(f.hit[0], 0);
  EXPECT_EQ(f.at(3, 3), 6);
  EXPECT_EQ(f.at(2, 4), 6);
  EXPECT_EQ(f.at(5, 3), 1);
}

TEST(HeightField, BadParametersThrow) {
  const Mesh m = box(0, 0, 0, 1, 1, 1);
  EXPECT_THROW((void)rasterize_top(m, 0.0), millnet::Error);
  EXPECT_THROW((void)rasterize_top(m, -1.0), millnet::Error);
  EXPECT_THROW((void)rasterize_top(m, std::nan("")), millnet::Error);
  EXPECT_THROW((void)rasterize_top(m, 1e-9), millnet::Error);
  EXPECT_THROW((void)resample(rasterize_top(m, 0.5), 1), millnet::Error);
  EXPECT_THROW((void)rasterize_top(Mesh{}, 1.0), millnet::Error);
}

TEST(HeightField, HeightMatrixIsTheRasterRowsByYPlusTheOffset) {
  HeightField hf;
  hf.nx = 3;
  hf.ny = 2;
  hf.z = {1, 2, 3,  // row 0 (min y)
          4, 5, 6};
  hf.hit = {1, 1, 1, 1, 0, 1};
  const Eigen::MatrixXd m = height_matrix(hf, -10.0);
  ASSERT_EQ(m.rows(), 2);
  ASSERT_EQ(m.cols(), 3);
  EXPECT_DOUBLE_EQ(m(0, 0), -9.0);
  EXPECT_DOUBLE_EQ(m(0, 2), -7.0);
  EXPECT_DOUBLE_EQ(m(1, 1), -5.0);  // the fill value shifts too
  EXPECT_DOUBLE_EQ(height_matrix(hf)(1, 2), 6.0);
}

// ---------------------------------------------------------------------------------------------
// The cell-max raster (rasterize_top_cells): each point the mesh's highest z over its cell.

namespace {

// Independent oracle for one triangle and one closed square [u0, u1] × [v0, v1]: the maximum of
// a linear function over their intersection lies at one of its vertices, which are among the
// triangle's vertices inside the square, the square's corners inside the triangle, and the
// crossings of the triangle's edges with the square's sides. Enumerates all of them (no
// clipping). Returns false when the two do not meet.
bool cell_max_oracle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double u0, double u1,
                     double v0, double v1, double& zmax) {
  constexpr double e = 1e-12;
  bool any = false;
  zmax = -std::numeric_limits<double>::infinity();
  auto take = [&](double z) {
    zmax = std::max(zmax, z);
    any = true;
  };
  auto in_sq = [&](double x, double y) { return x >= u0 - e && x <= u1 + e && y >= v0 - e && y <= v1 + e; };
  const Eigen::Vector3d t[3] = {a, b, c};
  for (const auto& p : t)
    if (in_sq(p.x(), p.y())) take(p.z());
  const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (std::abs(det) > 1e-12)
    for (const double x : {u0, u1})
      for (const double y : {v0, v1}) {
        const double l1 = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
        const double l2 = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
        const double l0 = 1 - l1 - l2;
        if (l0 >= -e && l1 >= -e && l2 >= -e) take(l0 * a.z() + l1 * b.z() + l2 * c.z());
      }
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& p = t[k];
    const Eigen::Vector3d& q = t[(k + 1) % 3];
    for (const double x : {u0, u1})
      if ((p.x() - x) * (q.x() - x) <= 0 && p.x() != q.x()) {
        const double s = (x - p.x()) / (q.x() - p.x());
        const double y = p.y() + s * (q.y() - p.y());
        if (y >= v0 - e && y <= v1 + e) take(p.z() + s * (q.z() - p.z()));
      }
    for (const double y : {v0, v1})
      if ((p.y() - y) * (q.y() - y) <= 0 && p.y() != q.y()) {
        const double s = (y - p.y()) / (q.y() - p.y());
        const double x = p.x() + s * (q.x() - p.x());
        if (x >= u0 - e && x <= u1 + e) take(p.z() + s * (q.z() - p.z()));
      }
  }
  return any;
}

}  // namespace

TEST(HeightFieldCells, TiltedPlaneTakesItsValueAtEachCellsHighCorner) {
  // z = 2 + 0.1x + 0.05y over 100 × 60 mm, raster step 1 from the origin: point (i, j)'s cell is
  // [j − ½, j + ½] × [i − ½, i + ½], cut to the plane's extent, and its highest point is the
  // corner (min(j + ½, 100), min(i + ½, 60)).
  const Mesh m = surface([](double x, double y) { return 2 + 0.1 * x + 0.05 * y; }, 0, 100, 0, 60, 1, 1);
  const HeightField f = rasterize_top_cells(m, 0, 0, 1, 101, 61);
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      ASSERT_TRUE(f.hit[static_cast<std::size_t>(i * f.nx + j)]) << i << "," << j;
      // (The cell is closed and widened by tol::raster_edge_eps = 1e-7 steps: 1.5e-8 mm here.)
      ASSERT_NEAR(f.at(i, j), 2 + 0.1 * std::min(j + 0.5, 100.0) + 0.05 * std::min(i + 0.5, 60.0), 2e-8)
          << i << "," << j;
    }
  // The point raster of the same plane lies half a cell lower (0.075 mm) everywhere inside.
  const HeightField g = rasterize_top(m, 0, 0, 1, 101, 61);
  EXPECT_NEAR(f.at(30, 40) - g.at(30, 40), 0.1 * 0.5 + 0.05 * 0.5, 2e-8);
}

TEST(HeightFieldCells, AThinFinBetweenRasterLinesIsSeen) {
  // A fin 0.2 mm thick and 10 mm high standing between the raster lines x = 3 and x = 4 (step 1):
  // no raster point lies under it, so the point raster misses it; the cells of x = 3 (to 3.5) and
  // x = 4 (from 3.5) meet it and take its top.
  const Mesh fin = box(3.2, 1.0, 0.0, 3.4, 5.0, 10.0);
  const HeightField p = rasterize_top(fin, 0, 0, 1, 8, 7);
  const HeightField c = rasterize_top_cells(fin, 0, 0, 1, 8, 7);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 8; ++j) {
      const auto k = static_cast<std::size_t>(i * 8 + j);
      EXPECT_EQ(p.hit[k], 0) << i << "," << j;
      const bool meets = j == 3 && i >= 1 && i <= 5;  // cell [2.5, 3.5] meets [3.2, 3.4]; rows 0.5..5.5 meet [1, 5]
      EXPECT_EQ(c.hit[k], meets ? 1 : 0) << i << "," << j;
      EXPECT_EQ(c.at(i, j), meets ? 10.0 : 0.0) << i << "," << j;
    }
}

TEST(HeightFieldCells, MatchesAVertexEnumerationOracleAndIsConservative) {
  for (unsigned seed : {4u, 5u}) {
    std::printf("seed %u\n", seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(0, 20), zz(-5, 5), small(-3, 3), unit(0, 1);
    Mesh m;
    const int n = 120;
    m.V.resize(3 * n + 3, 3);
    m.F.resize(n + 1, 3);
    for (int t = 0; t < n; ++t) {
      const double cx = xy(rng), cy = xy(rng);
      for (int k = 0; k < 3; ++k) m.V.row(3 * t + k) << cx + small(rng), cy + small(rng), zz(rng);
      m.F.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    }
    // And one vertical triangle (a wall in the plane y = 7.3).
    m.V.row(3 * n) << 2.1, 7.3, -4;
    m.V.row(3 * n + 1) << 9.6, 7.3, -4;
    m.V.row(3 * n + 2) << 5.0, 7.3, 6;
    m.F.row(n) << 3 * n, 3 * n + 1, 3 * n + 2;
    const double x0 = -3.1, y0 = -2.9, s = 0.37;
    const int nx = 75, ny = 74;
    const HeightField f = rasterize_top_cells(m, x0, y0, s, nx, ny);
    const HeightField pt = rasterize_top(m, x0, y0, s, nx, ny);
    const double h = s * (0.5 + 1e-7);  // the cell, widened by tol::raster_edge_eps steps
    int hits = 0;
    for (int i = 0; i < ny; ++i)
      for (int j = 0; j < nx; ++j) {
        const double cx = x0 + j * s, cy = y0 + i * s;
        bool any = false;
        double best = -std::numeric_limits<double>::infinity();
        for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
          double z;
          if (cell_max_oracle(m.V.row(m.F(t, 0)), m.V.row(m.F(t, 1)), m.V.row(m.F(t, 2)), cx - h, cx + h, cy - h,
                              cy + h, z)) {
            any = true;
            best = std::max(best, z);
          }
        }
        const auto k = static_cast<std::size_t>(i * nx + j);
        ASSERT_EQ(f.hit[k] != 0, any) << "seed " << seed << " " << i << "," << j;
        if (any) {
          ASSERT_NEAR(f.at(i, j), best, 1e-9) << "seed " << seed << " " << i << "," << j;
          ++hits;
        }
        ASSERT_GE(f.at(i, j), pt.at(i, j) - 1e-12) << "a cell holds its own point";
      }
    EXPECT_GT(hits, 1500);
    // The property rough relies on: every point of every triangle lies within half a diagonal of
    // a raster point at least as high (the one whose cell holds it).
    for (int r = 0; r < 20000; ++r) {
      const auto t = static_cast<Eigen::Index>(rng() % static_cast<unsigned>(m.F.rows()));
      double l1 = unit(rng), l2 = unit(rng);
      if (l1 + l2 > 1) {
        l1 = 1 - l1;
        l2 = 1 - l2;
      }
      const Eigen::Vector3d q = (1 - l1 - l2) * Eigen::Vector3d(m.V.row(m.F(t, 0))) +
                                l1 * Eigen::Vector3d(m.V.row(m.F(t, 1))) + l2 * Eigen::Vector3d(m.V.row(m.F(t, 2)));
      const int j = static_cast<int>(std::lround((q.x() - x0) / s)),
                i = static_cast<int>(std::lround((q.y() - y0) / s));
      ASSERT_GE(f.at(i, j), q.z() - 1e-9) << "seed " << seed << " sample " << r;
    }
  }
}

TEST(HeightFieldCells, ThreadCountInvariantBitwise) {
  const Mesh m = surface([](double x, double y) { return 3 * std::sin(0.3 * x) * std::cos(0.2 * y) + 0.01 * x * y; }, 0,
                         97.3, 0, 61.1, 250, 200);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const HeightField a = rasterize_top_cells(m, -1, -1, 0.13, 770, 490);
  omp_set_num_threads(2);
  const HeightField b = rasterize_top_cells(m, -1, -1, 0.13, 770, 490);
  omp_set_num_threads(saved);
  ASSERT_EQ(a.z.size(), b.z.size());
  EXPECT_EQ(std::memcmp(a.z.data(), b.z.data(), a.z.size() * sizeof(double)), 0);
  EXPECT_EQ(a.hit, b.hit);
}
