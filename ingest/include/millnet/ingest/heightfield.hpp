#pragma once
// Height sampling as Korosec & Kopac do it: the smallest rectangle around the part's footprint is
// covered by a raster of points; each is projected vertically onto the top surface, keeping the
// highest hit. Implemented as z-buffer rasterization over triangles (each triangle visits only the
// raster points under its XY bounding box), O(#F + raster points), OpenMP over row bands.
#include "millnet/core/budget.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace millnet::ingest {

/// Raster of top-surface heights. Point (i, j) sits at x = x0 + j·step, y = y0 + i·step
/// (rows = y from min y, cols = x from min x); the first and last rows/cols lie on the footprint
/// rectangle's edges (nx = ceil(width/step) + 1, step shrunk so that it spans it corner to corner).
struct HeightField {
  double x0 = 0, y0 = 0;
  double step_x = 1, step_y = 1;  ///< mm between raster points
  int nx = 0, ny = 0;
  std::vector<double> z;          ///< ny·nx, row-major; no hit ⇒ z_min (documented fill value)
  std::vector<std::uint8_t> hit;  ///< 1 where a triangle covers the point
  double z_min = 0, z_max = 0;    ///< lowest/highest vertex z of the mesh, mm
  [[nodiscard]] double at(int i, int j) const {
    return z[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)];
  }
  [[nodiscard]] double width() const { return step_x * (nx - 1); }
  [[nodiscard]] double height() const { return step_y * (ny - 1); }
};

/// Rasterizes the top surface at `raster_mm` spacing (> 0) over the mesh's XY bounding rectangle
/// (bounds of all of V). Rules, so that results are exact and reproducible:
///  * a raster point is covered by a triangle when it lies inside its XY projection or within
///    tol::raster_edge_eps raster steps outside an edge (inclusive: points exactly on shared
///    edges and vertices are always hit); its z is the plane's z there, clamped to the triangle's
///    z range; the highest z over all triangles is kept;
///  * a triangle that is vertical in XY (tol::vertical_triangle_rel) contributes its edges, so a
///    raster point exactly under a vertical wall takes the wall's top z;
///  * raster points hit by no triangle get z_min (the lowest vertex z) and hit = 0;
///  * OpenMP over bands of 16 rows, each owned by one thread: bitwise identical results for any
///    thread count. Cost O(#V + #F + Σ raster points in each triangle's XY bounding box).
/// Throws millnet::Error for an invalid mesh (see validate()) or a raster of more than 4·10⁸ points.
/// `limits`: raster_work(mesh, raster_mm) is checked against them first (issue 12).
[[nodiscard]] HeightField rasterize_top(const Mesh& mesh, double raster_mm, const WorkLimits& limits = {});

/// Same, over an explicit rectangle [x0, x0 + (nx−1)·step] × [y0, y0 + (ny−1)·step] (used for
/// roughing, where the stock is larger than the part). Points not under the part get z_min.
[[nodiscard]] HeightField rasterize_top(const Mesh& mesh, double x0, double y0, double step, int nx, int ny);

/// The same raster, but each point takes the highest z of the mesh over its cell (the square of
/// one step centred on it, closed) instead of at the point itself: a conservative raster, under
/// which every point of the top surface lies within half a raster diagonal of a raster point at
/// least as high. This is what slicing for roughing needs: on a slope between raster points the
/// point samples lie below material that the cell maxima see (rough: up to ≈ 0.1 mm of a 0.5 mm
/// allowance was missed on steep walls). Cells meeting no triangle get z_min and hit = 0. Same
/// threads rule as rasterize_top; cost O(#V + #F + Σ cells under each triangle's XY box widened
/// by half a step), each cell a 3D clip of the triangle by the cell's four sides.
[[nodiscard]] HeightField rasterize_top_cells(const Mesh& mesh, double x0, double y0, double step, int nx, int ny);

/// The raster as an ny × nx matrix (row i = y index, column j = x index) of z + offset (the fill
/// value z_min + offset where no triangle hit), e.g. heights in a program frame for a picture.
[[nodiscard]] Eigen::MatrixXd height_matrix(const HeightField& field, double offset = 0.0);

/// n×n model grid: heights in mm above the part's lowest point, rows = y (min y first), cols = x;
/// spans the footprint rectangle corner to corner. Bilinear interpolation of the raster.
/// Non-square footprints: the grid is stretched to n×n (grid column c sits at
/// x = x0 + c·width/(n−1), row r at y = y0 + r·height/(n−1)), as the paper clips each model to its
/// rectangle; the side lengths stay in footprint_x/footprint_y so that a/b can be an extra feature.
struct Grid {
  Eigen::MatrixXd h;       ///< n×n
  double footprint_x = 0;  ///< mm, width of the footprint rectangle (a)
  double footprint_y = 0;  ///< mm, height (b); a/b is kept as an extra feature
};

/// n ≥ 2; O(n²). Grid point (r, c) interpolates the raster at fractional index
/// (r·(ny−1)/(n−1), c·(nx−1)/(n−1)); h = z − field.z_min. Throws millnet::Error for n < 2.
[[nodiscard]] Grid resample(const HeightField& field, int n);

/// The cost of rasterize_top over a width × height (mm) footprint at `raster_mm` (issue 12): raster
/// points (⌈width/raster⌉ + 1)·(⌈height/raster⌉ + 1), exact as rasterize_top sizes them, 9 bytes each
/// (z and hit). `what` names the footprint ("mesh footprint", "stock"). Check it with
/// millnet::check_work before rasterizing.
[[nodiscard]] WorkEstimate raster_work(double width_mm, double height_mm, double raster_mm,
                                       const std::string& what = "footprint");
/// Same over the mesh's XY bounds (the footprint rasterize_top(mesh, raster_mm) covers).
[[nodiscard]] WorkEstimate raster_work(const Mesh& mesh, double raster_mm);

/// rasterize_top + resample.
[[nodiscard]] Grid sample_grid(const Mesh& mesh, double raster_mm, int n, const WorkLimits& limits = {});

}  // namespace millnet::ingest
