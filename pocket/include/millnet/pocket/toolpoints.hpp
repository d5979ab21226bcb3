#pragma once
// Tool points (Shin & Suh §3): a grid at the stepover spacing, kept where the tool disk (radius +
// stock to leave) fits inside the pocket without touching the boundary or an island.
#include "millnet/pocket/geometry.hpp"

#include <array>
#include <vector>

namespace millnet::pocket {

/// Grid frame: point (i, j) = origin + R(angle)·(j·spacing, i·spacing).
struct GridFrame {
  Vec2 origin{0, 0};
  double angle_deg = 0;
  double spacing = 5;
  [[nodiscard]] Vec2 at(int i, int j) const;
};

struct ToolPoints {
  GridFrame frame;
  std::vector<Vec2> pts;               ///< in a fixed order: by i (row), then j
  std::vector<std::array<int, 2>> ij;  ///< grid indices (i = row, j = column) of each point
};

/// The grid indices make_tool_points visits: rows i0..i1, columns j0..j1 (whole numbers held as
/// doubles, so that a too fine grid is counted, not overflowed). Empty boundary ⇒ an empty range.
struct GridRange {
  double i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  [[nodiscard]] double points() const { return (i1 - i0 + 1) * (j1 - j0 + 1); }
};
[[nodiscard]] GridRange grid_range(const Region& region, const GridFrame& frame);

/// All grid points whose disk of radius `clearance_mm` is inside the region (Clearance::point_ok).
[[nodiscard]] ToolPoints make_tool_points(const Region& region, const GridFrame& frame, double clearance_mm);

}  // namespace millnet::pocket
