#pragma once
// Triangle meshes in millnet: V is #V×3 vertex positions in mm (double), F is #F×3 vertex indices.
// Orientation of the part after prepare(): +Z is "up" (the side the tool comes from).
#include "millnet/core/budget.hpp"

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

/// The file's axis that points at the tool. Auto picks the face the part is machined from, for
/// mould-like parts that sit on a flat base (rule, see choose_up()):
///  1. for each candidate d in the order +Z, −Z, +Y, −Y, +X, −X: base(d) = area of the triangles
///     facing −d (normal within tol::auto_up_flat_deg) lying on the lowest plane along d (within
///     tol::auto_up_plane_mm); cap(d) = the same on the highest plane facing +d;
///  2. score(d) = base(d) − cap(d): a flat base under a non-flat working face scores high, while
///     a block's side walls (flat on both ends) score 0;
///  3. the largest score wins (ties: the earlier candidate); when no score is > 0 (open surfaces,
///     spheres), the direction with the largest projected area of triangles facing it wins
///     (normals from the winding), again +Z first on ties.
enum class Up { PosZ, NegZ, PosY, NegY, PosX, NegX, Auto };
/// "+z" | "-z" | "+y" | "-y" | "+x" | "-x" | "auto" (also "z" = "+z").
[[nodiscard]] Up parse_up(std::string_view s);
[[nodiscard]] std::string to_string(Up u);

/// How a CAD part (STEP .step/.stp, IGES .iges/.igs) becomes a mesh: Open CASCADE's mesher with
/// both deflections (each edge and face is refined until both hold), and which body to keep.
struct CadOptions {
  double chord_tolerance_mm = 0.005;    ///< linear deflection: largest facet-to-surface distance, mm
  double angular_deflection_rad = 0.2;  ///< largest angle between neighbouring facets' normals, rad
  /// "" = every solid, shell and free face together; else one body by name or 1-based index ("2").
  std::string body;
  /// Use what Open CASCADE could read of a damaged file (faces or roots lost, failed transfers,
  /// references to entities the file lacks); false (the default, config /mesh/allow_partial_cad)
  /// refuses such a read, counting what was lost (issue 42).
  bool allow_partial = false;
  /// The tessellation's estimated work and memory are checked against these before it runs
  /// (mesher steps against max_work, its memory against max_memory_bytes); max_memory_bytes also
  /// bounds the reader's process.
  WorkLimits limits{};
  /// The reader runs in a child process (cad_isolate.hpp) that a crash, a hang or runaway memory
  /// cannot take the caller down with; false reads in this process (for debugging).
  bool isolate = true;
  /// Wall-clock and CPU seconds the reader's process may take before it is stopped.
  double timeout_s = 600;
};

/// What reading a CAD part found (MeshReport::cad; empty for mesh formats).
struct CadReport {
  std::string format;             ///< "STEP" | "IGES"
  std::string file_unit;          ///< the file's declared length unit, e.g. "mm", "inch" ("" = not stated)
  double file_unit_mm = 1.0;      ///< mm per file unit (1 when not stated)
  bool units_overridden = false;  ///< --units / config units contradicted file_unit and won
  double chord_tolerance_mm = 0;  ///< as used
  double angular_deflection_rad = 0;
  std::vector<std::string> bodies;  ///< every body in the file, "name" or "body N" when unnamed
  std::string body;                 ///< the body kept ("" = all)
  std::size_t faces = 0;            ///< B-rep faces tessellated
  std::string units_note;           ///< one line for the user when the units were overridden ("" = none)
  /// What a read allowed to be partial (CadOptions::allow_partial) lost, one line ("" = complete).
  std::string partial;
  double estimated_triangles = 0;  ///< the tessellation's estimate, checked before it ran
  /// Per triangle of the mesh read, the B-rep face it tessellates: 1-based, in the order the faces
  /// of the kept shape are visited (a face placed twice counts twice, as in `faces`). Preparation
  /// keeps the triangles' order, so it indexes the prepared mesh too (issue 38: faces as a boundary).
  std::vector<std::int32_t> triangle_face;
  std::vector<std::string> face_names;  ///< per face (size `faces`), its name in the file ("" = none)
};

/// What was found and done while loading and preparing a mesh (reported, never fatal).
struct MeshReport {
  std::size_t triangles = 0;
  std::size_t degenerate_triangles = 0;                    ///< zero area (within ingest::tol::degenerate_area_mm2)
  std::size_t duplicate_triangles = 0;                     ///< same three vertices as an earlier triangle
  std::size_t non_manifold_edges = 0;                      ///< edges shared by more than two triangles
  std::size_t boundary_edges = 0;                          ///< edges used once (cracks, open shells)
  Up up_used = Up::PosZ;                                   ///< resolved axis when Auto was asked
  Eigen::Vector3d recentred_by = Eigen::Vector3d::Zero();  ///< mm subtracted (after units/up)
  std::vector<std::string> notes;                          ///< human-readable remarks (e.g. "stored normals ignored")
  bool is_cad = false;                                     ///< read from STEP/IGES: `cad` is filled
  CadReport cad;
};

/// Throws millnet::Error (prefixed with `source`) when the mesh has no triangles, an index out of
/// range, a NaN/inf coordinate, or no triangle with an area (all collinear or coincident). Fills the counting fields of *report when given.
void validate(const Mesh& mesh, const std::string& source, MeshReport* report = nullptr);

struct PrepareOptions {
  Units units = Units::mm;
  Up up = Up::PosZ;
  /// Translate so that the footprint's lower-left corner is at x = y = 0 and the lowest point at
  /// z = 0 (in double, before any float work): parts far from the origin lose no precision.
  bool recentre = true;
  /// A CAD file states its length unit and is read in mm from it; `units` then applies only when
  /// units_explicit (a --units flag, or a config's units other than the default "mm"), and a note says
  /// so when it contradicts the file. Mesh formats carry no unit: `units` always applies to them.
  bool units_explicit = false;
  CadOptions cad{};  ///< tessellation and body choice for CAD files (ignored for meshes)
};

/// Applies units, turns the chosen up axis onto +Z (a proper rotation, det = +1), recentres.
[[nodiscard]] Mesh prepare(const Mesh& raw, const PrepareOptions& options, MeshReport* report = nullptr);

/// Resolves Up::Auto for `mesh` by the rule above (other values are returned unchanged).
/// O(#F). `mesh` should be valid (see validate()).
[[nodiscard]] Up choose_up(const Mesh& mesh, Up requested = Up::Auto);

/// The proper rotation (det = +1) that turns the file axis `up` onto +Z (Up::Auto not allowed).
///   +Z: identity; −Z: 180° about X; +Y: +90° about X; −Y: −90° about X; +X: −90° about Y;
///   −X: +90° about Y.
[[nodiscard]] Eigen::Matrix3d up_rotation(Up up);

/// Axis-aligned bounds, mm.
struct Box3 {
  Eigen::Vector3d min, max;
};
[[nodiscard]] Box3 bounds(const Mesh& mesh);

}  // namespace millnet::ingest
