#pragma once
// A program's tool path seen from above, for pictures: the XY polylines of its cutting moves and of
// its rapids.
#include "millnet/gcode/program.hpp"

#include <array>
#include <vector>

namespace millnet::gcode {

using XyPolyline = std::vector<std::array<double, 2>>;

struct XyPaths {
  std::vector<XyPolyline> cuts;    ///< runs of feed moves (lines; arcs as their end points)
  std::vector<XyPolyline> rapids;  ///< runs of rapids that move in XY
};

/// Walks the moves in order. A move contributes its end point once the start position is known in
/// both X and Y (a move stating both): a feed move always (a plunge adds its XY again), a rapid only
/// when it moves in XY. Each run of one kind is one polyline starting at the previous position. O(n).
[[nodiscard]] XyPaths xy_paths(const Program& program);

}  // namespace millnet::gcode
