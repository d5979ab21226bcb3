#pragma once
// Point clouds ("x y z" sets, like the paper's VDA point files) made into a top-surface mesh.
#include "millnet/ingest/mesh.hpp"

namespace millnet::ingest {

/// Triangulates points (#P×3, any units) as a height field over XY: when the points sit on a
/// regular XY raster (every x of one set × every y of another, within tol::cloud_raster_rel of the
/// extent), two triangles per raster cell; otherwise a Delaunay triangulation of the XY positions
/// (OpenCV Subdiv2D, computed on centred and scaled coordinates so far-away clouds keep their
/// precision). Points with the same XY keep the highest z (the top surface). Triangles are CCW
/// seen from +Z. Cost: O(P log P).
/// Throws millnet::Error (prefixed with `source`) for fewer than 3 distinct XY points or when all
/// points are collinear in XY.
[[nodiscard]] Mesh triangulate_height_field(const Vertices& points, const std::string& source);

}  // namespace millnet::ingest
