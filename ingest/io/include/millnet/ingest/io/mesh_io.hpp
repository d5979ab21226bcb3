#pragma once
// Mesh files (target millnet::ingest_io; assimp lives in one .cpp behind this header).
#include "millnet/ingest/mesh.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::ingest {

/// Loads a triangle mesh — binary STL, PLY (ASCII/binary) and OFF by millnet's own readers, ASCII
/// STL, OBJ, 3MF, glTF through assimp, STEP (.step/.stp) and IGES (.iges/.igs) parts through Open
/// CASCADE (tessellated with CadOptions' defaults; in mm from the file's own unit) — or a point cloud ("x y z" per line, extensions
/// .xyz/.pts/.txt/.asc; triangulated as a height field over XY). Polygons become triangle fans.
/// Coordinates exactly as in the file (no units, no up, no recentring: see prepare()).
/// Throws millnet::Error naming the file (and line or byte offset): missing, not a regular file,
/// unreadable, unknown format, malformed (counts the file cannot hold, indices out of range, faces
/// of fewer than 3 vertices), no triangles, NaN/inf.
[[nodiscard]] Mesh load_mesh(const std::filesystem::path& path, MeshReport* report = nullptr);

/// The same, with the tessellation and body choice for CAD files (report->cad tells what was read:
/// the file's unit, its bodies, the deflections used). A CAD file in a build without Open CASCADE
/// (MILLNET_CAD=OFF) throws "<file>: built without CAD support (…)". A CAD file is read in a child
/// process that cannot take the caller down, and a damaged or hostile one is one millnet::Error
/// naming it (what was lost, a crash, a size or a tessellation beyond cad.limits: issue 42).
[[nodiscard]] Mesh load_mesh(const std::filesystem::path& path, const CadOptions& cad, MeshReport* report = nullptr);

/// True when this build reads STEP/IGES (CMake option MILLNET_CAD).
[[nodiscard]] bool cad_supported();

/// load_mesh then prepare (units, up, recentring): the part as every command works on it. A CAD file
/// keeps its own unit unless options.units_explicit; then `units` reinterprets its numbers, and
/// report->cad.units_note (also in notes) says so when that contradicts the file's unit.
[[nodiscard]] Mesh load_prepared(const std::filesystem::path& path, const PrepareOptions& options,
                                 MeshReport* report = nullptr);

enum class MeshFormatKind { Mesh, PointCloud, Cad };

/// A file format load_mesh reads: the registry of mesh formats (issue 36 §4). Adding one: its reader
/// (a function in its own source, or a line naming assimp's) and its entry in mesh_formats()
/// (ingest/io/mesh_io.cpp); the folders of `learn`, `finish` and `run` pick it up from there.
struct MeshFormat {
  std::string_view name;  ///< for messages and the README's table
  MeshFormatKind kind = MeshFormatKind::Mesh;
  std::vector<std::string> extensions;  ///< lower case, with the dot
  /// Reads the file (it exists and opens); the mesh is validated after it.
  Mesh (*read)(const std::filesystem::path& path, const CadOptions& cad, MeshReport* report) = nullptr;
};

/// The registry, in the order of the README's table.
[[nodiscard]] const std::vector<MeshFormat>& mesh_formats();

/// The extensions load_mesh reads (lower case, with the dot), from mesh_formats(): the one list the
/// commands use to pick mesh files out of folders.
[[nodiscard]] const std::vector<std::string>& mesh_extensions();

/// Point-cloud extensions ("x y z" text), a subset of mesh_extensions().
[[nodiscard]] const std::vector<std::string>& point_cloud_extensions();

/// Writes a binary STL (80-byte header, little-endian float32, facet normals computed), atomically.
void save_stl_binary(const Mesh& mesh, const std::filesystem::path& path, std::string_view header = "millnet");

}  // namespace millnet::ingest
