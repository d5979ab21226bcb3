#pragma once
// Mesh files (target millnet::ingest_io; assimp lives in one .cpp behind this header).
#include "millnet/ingest/mesh.hpp"

#include <filesystem>

namespace millnet::ingest {

/// Loads a triangle mesh with assimp (STL binary/ASCII, OBJ, PLY, OFF, 3MF, glTF, …) or a point
/// cloud ("x y z" per line, extensions .xyz/.pts/.txt/.asc; triangulated as a height field over XY).
/// Coordinates exactly as in the file (no units, no up, no recentring: see prepare()).
/// Throws millnet::Error naming the file: missing/unreadable, unknown format, no triangles, NaN/inf.
[[nodiscard]] Mesh load_mesh(const std::filesystem::path& path, MeshReport* report = nullptr);

/// Writes a binary STL (80-byte header, little-endian float32, facet normals computed), atomically.
void save_stl_binary(const Mesh& mesh, const std::filesystem::path& path, std::string_view header = "millnet");

}  // namespace millnet::ingest
