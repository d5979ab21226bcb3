#pragma once
// The default training set: parametric mould-like parts in five families, one per named strategy,
// each family the textbook geometric reason for its strategy (see datasets/README.md):
//   1 profile + Z finishing, slope mode     — flat areas with steep walls (stepped plateaus, pads)
//   2 3D/profile finishing                   — gentle free-form (broad low bumps, saddle)
//   3 profile finishing, scallop-height mode — varying curvature (ridges from sharp to flat)
//   4 Z-level finishing                      — steep walls / deep cavities (deep pockets, tall boss)
//   5 profile finishing, equidistant         — shallow uniform slopes (planes, roofs, gentle cones)
// Every part is a closed, consistently oriented (outward normals) height-field solid in mm: a top
// surface over the rectangle [0,a]×[0,b] (a, b in 100–130 mm, the same range for every family),
// vertical side walls and a flat bottom at z = 0; the top's lowest point is 5–12 mm above it.
// Mesh layout (relied on by tests): the first res_x·res_y vertices are the top grid, row-major,
// vertex (i, j) at x = a·j/(res_x−1), y = b·i/(res_y−1); the first 2·(res_x−1)·(res_y−1) faces
// are the top surface (two per grid cell).
#include "millnet/ingest/mesh.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace millnet::datasets {

enum class Family : int {
  SteepPlateaus = 1,     ///< strategy 1
  GentleFreeForm = 2,    ///< strategy 2
  VaryingCurvature = 3,  ///< strategy 3
  DeepCavity = 4,        ///< strategy 4
  ShallowSlopes = 5,     ///< strategy 5
};
inline constexpr int kFamilies = 5;

/// "steep_plateaus", "gentle_freeform", "varying_curvature", "deep_cavity", "shallow_slopes".
[[nodiscard]] std::string family_name(Family f);

struct GeneratedMesh {
  ingest::Mesh mesh;
  int res_x = 0, res_y = 0;  ///< top-grid vertices along x and y
  double a = 0, b = 0;       ///< footprint, mm
  std::string kind;          ///< sub-type within the family (e.g. "pocket", "boss", "roof")
};

/// Which generated library: the five textbook families (this header) or the tool-shop parts
/// (shop_parts.hpp, issue 39 §2).
enum class Library { Families, Shop };

struct GenerateParams {
  std::uint64_t seed = 7;
  int per_family = 6;    ///< families: parts per family (≥ 1)
  int resolution = 110;  ///< families: top-grid vertices per side (≥ 8): 110 ⇒ ~25k triangles per part
  Library library = Library::Families;
  int count = 500;          ///< shop: parts in the library (≥ 1)
  double spacing_mm = 0.8;  ///< shop: top-grid spacing, mm
};

/// One part of a family, deterministic in (family, index, seed). index ≥ 0 selects the sub-type
/// (index mod the family's kinds) and, with the seed, the parameters. O(resolution²).
[[nodiscard]] GeneratedMesh make_part(Family family, int index, std::uint64_t seed, int resolution = 110);

/// A generated part as listed in <dir>/parts.csv.
struct GeneratedPart {
  std::string name;            ///< e.g. "s4_deep_cavity_03"
  std::filesystem::path file;  ///< absolute or as <dir>/<name>.stl
  int label = 0;               ///< strategy slot 1..5
};

/// Writes per_family parts of every family as binary STL (<dir>/<name>.stl, atomically) and
/// <dir>/parts.csv ("name,file,label", file relative to dir); returns the list in family order.
/// Same params ⇒ identical bytes. O(families · per_family · resolution²).
std::vector<GeneratedPart> generate_default_parts(const std::filesystem::path& dir, const GenerateParams& params = {});

/// The library `params` names: generate_default_parts for the families, generate_shop_parts
/// (shop_parts.hpp) for the tool-shop parts (labels 0: they are labelled by simulation).
std::vector<GeneratedPart> generate_library(const std::filesystem::path& dir, const GenerateParams& params);

/// The top surface's heights of a generated part (rows = y from y = 0, cols = x), res_y × res_x.
[[nodiscard]] Eigen::MatrixXd top_heights(const GeneratedMesh& g);

/// The first `per_family` parts of every family of the library `params` names, in memory, family by
/// family, each with its library name (for pictures: `millnet dataset --gallery`).
struct GalleryPart {
  std::string name;
  GeneratedMesh part;
};
[[nodiscard]] std::vector<GalleryPart> library_gallery(const GenerateParams& params, int per_family);

}  // namespace millnet::datasets
