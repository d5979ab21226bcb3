#pragma once
// Rest machining's internals shared by rest.cpp and rest_stock.cpp (not installed).
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace millnet::finish::detail {

/// Triangle f's unit normal (+Z for a degenerate one or an index out of range).
inline Eigen::Vector3d unit_normal(const ingest::Mesh& mesh, std::ptrdiff_t f) {
  if (f < 0 || f >= mesh.F.rows()) return Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  return n.norm() > 0 ? Eigen::Vector3d(n / n.norm()) : Eigen::Vector3d::UnitZ();
}

/// The pieces of `passes` where the tool removes rest: a point cuts when the material at its
/// contact (a drop at its XY, regions.material) exceeds a quarter of the threshold; each cutting
/// point keeps the points within a quarter of the tool's radius (path length) on either side; runs
/// of kept points are the pieces. Passes in parallel, each on its own: any thread count. O(points)
/// drops.
[[nodiscard]] std::vector<Pass> trim_to_rest(const std::vector<Pass>& passes, const DropCutter& tool,
                                             const ingest::Mesh& mesh, const RestRegions& regions);

}  // namespace millnet::finish::detail
