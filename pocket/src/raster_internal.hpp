#pragma once
// Cell rasters of a region, shared by the adaptive planner's cleared-area raster and the links
// through cut material (private to pocket/). Cells are h mm squares; cell (x, y) has its centre at
// lo + ((x + ½)·h, (y + ½)·h); row-major, rows = y.
#include "millnet/pocket/geometry.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace millnet::pocket::raster {

/// Row-major index of (x, y) in a grid nx wide.
[[nodiscard]] inline std::size_t lin(int x, int y, int nx) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x);
}

/// The box of the region's boundary grown by margin, as a grid of h cells: lo and the counts.
/// Throws millnet::Error naming `who` when it would exceed max_cells.
struct Grid {
  Vec2 lo;
  int nx = 0, ny = 0;
  double h = 0;
  [[nodiscard]] Vec2 centre(int x, int y) const { return lo + Vec2((x + 0.5) * h, (y + 0.5) * h); }
  [[nodiscard]] std::size_t size() const { return lin(0, ny, nx); }
};
[[nodiscard]] Grid grid_of(const Region& region, double h, double margin, const char* who, double max_cells = 4e7);
/// The number of cells grid_of(region, h, margin, …) would make (without making or refusing it).
[[nodiscard]] double cells_of(const Region& region, double h, double margin);

/// 1 for the cells whose centre lies inside the region (boundary minus islands), else 0: filled row
/// by row between the crossings of the row's centre line with the flattened loops (even-odd:
/// islands lie inside the boundary and apart). O(rows · loop vertices + cells).
[[nodiscard]] std::vector<std::uint8_t> material(const Region& region, const Grid& g);

/// Squared Euclidean distance (in cells) from every cell to the nearest seed cell (seed ≠ 0),
/// +inf where there is no seed: OpenCV's exact transform (cv::DIST_MASK_PRECISE), as ingest's
/// Z-level outlines use it. O(cells).
[[nodiscard]] std::vector<double> edt(const std::vector<std::uint8_t>& seed, int nx, int ny);

}  // namespace millnet::pocket::raster
