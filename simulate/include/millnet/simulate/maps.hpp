#pragma once
// Per-cell maps around the z-map (GridSpec layout: row-major, rows = y): the design surface from a
// height field, and block means that shrink a map for a picture.
#include "millnet/ingest/heightfield.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace millnet::simulate {

/// The design surface of a z-map grid from a height field rasterized at the cell centres (one raster
/// point per cell): z + z_shift where a triangle covers the point, NaN elsewhere (off the part).
/// Same size and order as field.z.
[[nodiscard]] std::vector<double> design_heights(const ingest::HeightField& field, double z_shift);

/// Block means of a row-major nx × ny map (rows = y), so that neither side has more than
/// max_cells blocks: k = ⌈max(nx, ny) / max_cells⌉ cells per block side (the last row and column of
/// blocks may be partial). Non-finite cells are skipped; a block with none gets `empty`. Returns a
/// ⌈ny/k⌉ × ⌈nx/k⌉ matrix. v.size() must be nx·ny; max_cells ≥ 1. O(nx·ny).
[[nodiscard]] Eigen::MatrixXd block_means(const std::vector<double>& v, std::size_t nx, std::size_t ny,
                                          std::size_t max_cells, double empty);
/// The same of a float map (an Ra map), each value widened to double as it is summed.
[[nodiscard]] Eigen::MatrixXd block_means(const std::vector<float>& v, std::size_t nx, std::size_t ny,
                                          std::size_t max_cells, double empty);

}  // namespace millnet::simulate
