#include "millnet/datasets/features.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::datasets {

ModelVector model_vector(const ingest::Mesh& mesh, const augment::Variant& variant, double raster_mm, int grid,
                         const WorkLimits& limits) {
  const ingest::Grid g = ingest::sample_grid(augment::apply(mesh, variant), raster_mm, grid, limits);
  const auto n = static_cast<Eigen::Index>(grid);
  if (g.h.rows() != n || g.h.cols() != n)
    throw Error("sampler returned a " + std::to_string(g.h.rows()) + "×" + std::to_string(g.h.cols()) + " grid");
  ModelVector mv;
  mv.inputs.resize(static_cast<std::size_t>(n * n));
  for (Eigen::Index i = 0; i < n; ++i)  // row = y, col = x
    for (Eigen::Index j = 0; j < n; ++j) mv.inputs[static_cast<std::size_t>(i * n + j)] = g.h(i, j);
  mv.aspect = g.footprint_y > 0 ? g.footprint_x / g.footprint_y : 0.0;
  return mv;
}

double wall_share(const ingest::Mesh& m) {
  const double cos_wall = std::cos(kWallSlopeDeg * std::numbers::pi / 180.0);
  double area = 0, wall = 0;
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {  // O(triangles)
    const Eigen::Vector3d a = m.V.row(m.F(t, 0)), b = m.V.row(m.F(t, 1)), c = m.V.row(m.F(t, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0) || n.z() / len < 1e-3) continue;  // the sides and the bottom are not machined
    area += len / 2;
    if (n.z() / len < cos_wall) wall += len / 2;
  }
  return area > 0 ? wall / area : 0.0;
}

ModelVectors model_vectors(const ingest::Mesh& mesh, const std::string& source, const FeatureSpec& spec,
                           const WorkLimits& limits) {
  ModelVectors out;
  out.variants = augment::make_variants(source, spec.augment);
  const auto cols = static_cast<Eigen::Index>(spec.grid) * static_cast<Eigen::Index>(spec.grid);
  const auto copies = static_cast<Eigen::Index>(std::max(0, spec.wall_share_copies));
  out.inputs.resize(static_cast<Eigen::Index>(out.variants.size()), cols + copies);
  const double walls = copies > 0 ? wall_share(mesh) : 0.0;
  for (std::size_t v = 0; v < out.variants.size(); ++v) {
    const ModelVector mv = model_vector(mesh, out.variants[v], spec.raster_mm, spec.grid, limits);
    for (Eigen::Index c = 0; c < cols; ++c)
      out.inputs(static_cast<Eigen::Index>(v), c) = mv.inputs[static_cast<std::size_t>(c)];
    for (Eigen::Index c = 0; c < copies; ++c) out.inputs(static_cast<Eigen::Index>(v), cols + c) = walls;
  }
  return out;
}

}  // namespace millnet::datasets
