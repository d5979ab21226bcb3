#pragma once
// Triangle meshes in millnet: V is #V×3 vertex positions in mm (double), F is #F×3 vertex indices.
// Orientation of the part after prepare(): +Z is "up" (the side the tool comes from).
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::ingest {

using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Faces = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct Mesh {
  Vertices V;  ///< #V×3, mm
  Faces F;     ///< #F×3, indices into V
};

enum class Units { mm, inch, m };
/// "mm" | "inch" | "in" | "m"; throws millnet::Error naming the accepted values.
[[nodiscard]] Units parse_units(std::string_view s);
[[nodiscard]] double units_to_mm(Units u);  ///< 1, 25.4, 1000

enum class Up { PosZ, NegZ, PosY, NegY, PosX, NegX, Auto };
/// "+z" | "-z" | "+y" | "-y" | "+x" | "-x" | "auto" (also "z" = "+z").
[[nodiscard]] Up parse_up(std::string_view s);
[[nodiscard]] std::string to_string(Up u);

/// What was found and done while loading and preparing a mesh (reported, never fatal).
struct MeshReport {
  std::size_t triangles = 0;
  std::size_t degenerate_triangles = 0;   ///< zero area (within ingest::tol::degenerate_area_mm2)
  std::size_t duplicate_triangles = 0;    ///< same three vertices as an earlier triangle
  std::size_t non_manifold_edges = 0;     ///< edges shared by more than two triangles
  std::size_t boundary_edges = 0;         ///< edges used once (cracks, open shells)
  Up up_used = Up::PosZ;                  ///< resolved axis when Auto was asked
  Eigen::Vector3d recentred_by = Eigen::Vector3d::Zero();  ///< mm subtracted (after units/up)
  std::vector<std::string> notes;         ///< human-readable remarks (e.g. "stored normals ignored")
};

/// Throws millnet::Error (prefixed with `source`) when the mesh has no triangles, an index out of
/// range, or a NaN/inf coordinate. Fills the counting fields of *report when given.
void validate(const Mesh& mesh, const std::string& source, MeshReport* report = nullptr);

struct PrepareOptions {
  Units units = Units::mm;
  Up up = Up::PosZ;
  /// Translate so that the footprint's lower-left corner is at x = y = 0 and the lowest point at
  /// z = 0 (in double, before any float work): parts far from the origin lose no precision.
  bool recentre = true;
};

/// Applies units, turns the chosen up axis onto +Z (a proper rotation, det = +1), recentres.
[[nodiscard]] Mesh prepare(const Mesh& raw, const PrepareOptions& options, MeshReport* report = nullptr);

/// Axis-aligned bounds, mm.
struct Box3 {
  Eigen::Vector3d min, max;
};
[[nodiscard]] Box3 bounds(const Mesh& mesh);

}  // namespace millnet::ingest
