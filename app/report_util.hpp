#pragma once
// Small adapters from module results to report pictures, shared by several commands.
#include "millnet/ingest/heightfield.hpp"
#include "millnet/report/plots.hpp"

#include <filesystem>
#include <string>

namespace millnet::app {

/// Heat map of a model grid in mm: cell centres at the grid points, which span the footprint.
inline void write_grid_png(const std::filesystem::path& path, const ingest::Grid& grid, const std::string& name) {
  report::HeatMapOptions o;
  const auto n = static_cast<double>(grid.h.cols());
  const double dx = n > 1 ? grid.footprint_x / (n - 1) : 1, dy = n > 1 ? grid.footprint_y / (n - 1) : 1;
  o.extent_mm = std::array<double, 4>{-dx / 2, grid.footprint_x + dx / 2, -dy / 2, grid.footprint_y + dy / 2};
  o.annotate = grid.h.rows() <= 20;
  (void)report::heat_map_png(
      path, grid.h, name + ": " + std::to_string(grid.h.rows()) + "x" + std::to_string(grid.h.cols()) + " height grid",
      "height above lowest point (mm)", o);
}

}  // namespace millnet::app
