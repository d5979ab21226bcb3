#pragma once
// Height sampling as Korosec & Kopac do it: the smallest rectangle around the part's footprint is
// covered by a raster of points; each is projected vertically onto the top surface, keeping the
// highest hit. Implemented as z-buffer rasterization over triangles (each triangle visits only the
// raster points under its XY bounding box), O(#F + raster points), OpenMP over row bands.
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace millnet::ingest {

/// Raster of top-surface heights. Point (i, j) sits at x = x0 + j·step, y = y0 + i·step
/// (rows = y from min y, cols = x from min x); the first and last rows/cols lie on the footprint
/// rectangle's edges (nx = ceil(width/step) + 1, step shrunk so that it spans it corner to corner).
struct HeightField {
  double x0 = 0, y0 = 0;
  double step_x = 1, step_y = 1;       ///< mm between raster points
  int nx = 0, ny = 0;
  std::vector<double> z;               ///< ny·nx, row-major; no hit ⇒ z_min (documented fill value)
  std::vector<std::uint8_t> hit;       ///< 1 where a triangle covers the point
  double z_min = 0, z_max = 0;         ///< lowest/highest vertex z of the mesh, mm
  [[nodiscard]] double at(int i, int j) const { return z[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)]; }
  [[nodiscard]] double width() const { return step_x * (nx - 1); }
  [[nodiscard]] double height() const { return step_y * (ny - 1); }
};

/// Rasterizes the top surface at `raster_mm` spacing (> 0) over the mesh's XY bounding rectangle.
[[nodiscard]] HeightField rasterize_top(const Mesh& mesh, double raster_mm);

/// Same, over an explicit rectangle [x0, x0 + (nx−1)·step] × [y0, y0 + (ny−1)·step] (used for
/// roughing, where the stock is larger than the part). Points not under the part get z_min.
[[nodiscard]] HeightField rasterize_top(const Mesh& mesh, double x0, double y0, double step, int nx, int ny);

/// n×n model grid: heights in mm above the part's lowest point, rows = y (min y first), cols = x;
/// spans the footprint rectangle corner to corner. Bilinear interpolation of the raster.
struct Grid {
  Eigen::MatrixXd h;              ///< n×n
  double footprint_x = 0;         ///< mm, width of the footprint rectangle (a)
  double footprint_y = 0;         ///< mm, height (b); a/b is kept as an extra feature
};

[[nodiscard]] Grid resample(const HeightField& field, int n);

/// rasterize_top + resample.
[[nodiscard]] Grid sample_grid(const Mesh& mesh, double raster_mm, int n);

}  // namespace millnet::ingest
