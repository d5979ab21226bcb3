#pragma once
// Augmented variants of a part (Korosec & Kopac: each model rotated through a list of angles, and
// the same again after turning it by 180°). A Variant is a recipe; apply() makes the mesh.
#include "millnet/ingest/mesh.hpp"

#include <string>
#include <vector>

namespace millnet::augment {

enum class Axis { X, Y, Z };
[[nodiscard]] Axis parse_axis(std::string_view s);  ///< "x" | "y" | "z"; throws millnet::Error
[[nodiscard]] char to_char(Axis a);

struct Variant {
  std::string source;     ///< the part this variant came from (file stem or path)
  Axis axis = Axis::X;    ///< rotation axis
  double angle_deg = 0;   ///< rotation angle about `axis`, degrees, right-hand rule
  bool flip = false;      ///< turned by 180° about Z (the up axis) before rotating
};

struct AugmentParams {
  std::vector<double> angles_deg;      ///< default −50…+50 step 10 (see defaults())
  std::vector<Axis> axes{Axis::X};     ///< each angle is applied about each axis in turn
  bool flip = true;                    ///< add the flipped copy of every rotation
  [[nodiscard]] static AugmentParams defaults();
};

/// Variants in a fixed, documented order: flip ∈ {false, true} × axes × angles.
[[nodiscard]] std::vector<Variant> make_variants(const std::string& source, const AugmentParams& params);

/// The rotated/flipped mesh (rotation about the part's bounding-box centre; result is not recentred).
[[nodiscard]] ingest::Mesh apply(const ingest::Mesh& mesh, const Variant& variant);

}  // namespace millnet::augment
