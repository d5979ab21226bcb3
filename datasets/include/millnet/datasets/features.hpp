#pragma once
// Mesh → model vectors, the one path shared by dataset building and prediction:
//   prepared mesh → rotated/flipped variants (augment) → n×n height grid per variant (ingest) →
//   one row of n² heights per variant (row-major, row = y, col = x).
//   ModelVectors mv = model_vectors(mesh, "part", spec);   // mv.inputs: M × n²
#include "millnet/augment/variants.hpp"
#include "millnet/core/budget.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace millnet::datasets {

/// How a part is turned into model vectors (a trained model's sampling: the same spec must be used
/// for its training table and for every prediction).
struct FeatureSpec {
  double raster_mm = 1.0;  ///< > 0
  int grid = 15;           ///< n of the n×n grid, ≥ 2
  augment::AugmentParams augment = augment::AugmentParams::defaults();
  /// The part's wall share (wall_share, of the prepared part: the same on every variant) follows
  /// the heights this many times (a model trained with it, classifier::InputSpec); 0: heights only.
  int wall_share_copies = 0;
};

/// One variant's model vector.
struct ModelVector {
  std::vector<double> inputs;  ///< n² heights, row-major (row = y, col = x)
  double aspect = 0;           ///< footprint x / y of the variant's grid (0 when y = 0)
};

/// apply(mesh, variant) → sample_grid(raster_mm, grid) → one vector. Throws millnet::Error when the
/// sampler does not return an n×n grid, or when the variant's raster exceeds `limits`
/// (ingest::raster_work, issue 12). O(triangles + raster points).
[[nodiscard]] ModelVector model_vector(const ingest::Mesh& mesh, const augment::Variant& variant, double raster_mm,
                                       int grid, const WorkLimits& limits = {});

/// Facets steeper than this are walls (wall_share), degrees.
inline constexpr double kWallSlopeDeg = 60.0;

/// The part's wall share: of its upward-facing facets (the machined surface seen from above: a
/// facet whose normal has n_z / |n| ≥ 1e-3; the vertical sides and the bottom are left out), the
/// area share steeper than kWallSlopeDeg. In [0, 1]; 0 for a mesh with no upward facet. What a
/// raster finish leaves out of the specification and a 15×15 height grid does not see (issue 39
/// §3). O(triangles).
[[nodiscard]] double wall_share(const ingest::Mesh& mesh);

struct ModelVectors {
  std::vector<augment::Variant> variants;  ///< augment::make_variants order
  Eigen::MatrixXd inputs;                  ///< one row per variant, n² (+ wall share copies) columns
};

/// Every variant of `spec.augment` of the prepared `mesh` (`source` names the part, as in
/// make_variants): its n² heights, then spec.wall_share_copies copies of the part's wall share.
/// O(variants · (triangles + raster points)).
[[nodiscard]] ModelVectors model_vectors(const ingest::Mesh& mesh, const std::string& source, const FeatureSpec& spec,
                                         const WorkLimits& limits = {});

}  // namespace millnet::datasets
