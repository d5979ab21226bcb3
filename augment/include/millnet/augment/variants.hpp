#pragma once
// Augmented variants of a part (Korosec & Kopac: each model rotated through a list of angles, and
// the same again after turning it by 180°). A Variant is a recipe; apply() makes the mesh.
//
// The paper's counts do not agree ("ten rotations", "20 additional sub-models", "24 vectors per
// model" for −50°…+50° in 10° steps). Our reading, and the default: the 11 angles −50, −40, …, +50
// (0 included, so the unrotated part is one of them) about X, and the same 11 after the 180° turn,
// i.e. 22 variants (vectors) per part. "Turned upside down" would put a mould part's flat base on
// top and sample nothing but a plane, so the 180° turn is about the up axis Z (the part keeps
// facing the tool, its features swap ends); rotations about X then tilt it by ≤ 50°.
#include "millnet/ingest/mesh.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace millnet::augment {

enum class Axis { X, Y, Z };
[[nodiscard]] Axis parse_axis(std::string_view s);  ///< "x" | "y" | "z"; throws millnet::Error
[[nodiscard]] char to_char(Axis a);

struct Variant {
  std::string source;    ///< the part this variant came from (file stem or path)
  Axis axis = Axis::X;   ///< rotation axis
  double angle_deg = 0;  ///< rotation angle about `axis`, degrees, right-hand rule
  bool flip = false;     ///< turned by 180° about Z (the up axis) before rotating
};

struct AugmentParams {
  std::vector<double> angles_deg;   ///< default −50…+50 step 10 (see defaults())
  std::vector<Axis> axes{Axis::X};  ///< each angle is applied about each axis in turn
  bool flip = true;                 ///< add the flipped copy of every rotation
  [[nodiscard]] static AugmentParams defaults();
};

/// Variants in a fixed, documented order: flip ∈ {false, true} × axes × angles (outermost first).
/// Throws millnet::Error when angles_deg or axes is empty or an angle is not finite.
[[nodiscard]] std::vector<Variant> make_variants(const std::string& source, const AugmentParams& params);

/// The rotated/flipped mesh: p' = R_axis(angle)·R_z(180° if flip)·(p − c) + c, c = the part's
/// bounding-box centre (result is not recentred; sampling uses its own footprint). O(#V).
[[nodiscard]] ingest::Mesh apply(const ingest::Mesh& mesh, const Variant& variant);

}  // namespace millnet::augment
