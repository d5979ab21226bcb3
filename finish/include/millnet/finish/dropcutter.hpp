#pragma once
// Drop-cutter against a triangle mesh (ARCHITECTURE.md, finish/): for a vertical cutter axis at
// (x, y), the lowest tip height z at which the cutter touches the mesh and nowhere penetrates it.
// Exact (closed form or robust 1-D root finding to 1e-12 mm), not sampled: facet, edge and vertex
// contacts for flat, ball and bull cutters.
//
// The mesh is prepared (ingest::prepare): mm, +Z up. A spatial index over the triangles' XY
// extents grown by the cutter radius is built once in the constructor; queries are const and
// thread-safe.
#include "millnet/finish/cutter.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace millnet::finish {

enum class Contact : std::uint8_t { None, Facet, Edge, Vertex };

/// One cutter location. When nothing lies under the cutter, contact = None and z = -infinity.
struct CLPoint {
  double x = 0, y = 0;
  double z = -std::numeric_limits<double>::infinity();  ///< tip height, mm
  Contact contact = Contact::None;
  Eigen::Vector3d cc = Eigen::Vector3d::Zero();           ///< cutter-contact point on the mesh
  std::int32_t triangle = -1;                             ///< index of the touched triangle
};

class DropCutter {
public:
  /// Builds the index: O(#F). Throws millnet::Error for an invalid mesh or cutter.
  DropCutter(const ingest::Mesh& mesh, const Cutter& cutter);
  ~DropCutter();
  DropCutter(DropCutter&&) noexcept;
  DropCutter& operator=(DropCutter&&) noexcept;

  [[nodiscard]] const Cutter& cutter() const;
  /// One query: O(triangles whose grown XY box contains (x, y)).
  [[nodiscard]] CLPoint drop(double x, double y) const;
  /// Many queries, OpenMP over the points, results identical for any thread count.
  [[nodiscard]] std::vector<CLPoint> drop(const std::vector<Eigen::Vector2d>& xy) const;
  /// Tip heights on a grid x = x0 + j·step, y = y0 + i·step (row-major, rows = y), -infinity where
  /// nothing lies under the cutter.
  [[nodiscard]] std::vector<double> drop_grid(double x0, double y0, double step, int nx, int ny) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The reference: every triangle tested, no index. O(#F) per query; for tests and benchmarks.
[[nodiscard]] CLPoint drop_brute_force(const ingest::Mesh& mesh, const Cutter& cutter, double x, double y);

}  // namespace millnet::finish
