#pragma once
// Drop-cutter against a triangle mesh (ARCHITECTURE.md, finish/): for a vertical cutter axis at
// (x, y), the lowest tip height z at which the cutter touches the mesh and nowhere penetrates it.
// Exact (closed form or robust 1-D root finding to 1e-12 mm), not sampled: facet, edge and vertex
// contacts for flat, ball and bull cutters.
//
// The mesh is prepared (ingest::prepare): mm, +Z up. A spatial index over the triangles' XY
// extents grown by the cutter radius is built once in the constructor (a uniform grid of cells of
// side ≥ R/2; ~0.05–0.2 s for 1M triangles); the DropCutter keeps its own copy of the mesh, and
// queries are const and thread-safe.
//
// No contact: where no triangle lies under the cutter's disk (|p_xy − axis| ≤ R), the result is
// contact = None, z = -infinity, triangle = -1 (drop_grid: -infinity). Callers decide what that
// means (e.g. stock bottom or outside the part).
//
// Exactness: z is the maximum over triangles of each triangle's contact height, computed the same
// way by drop(), drop_grid() and drop_brute_force(), so the three agree bit for bit; the index
// only skips triangles that fall short of the best contact by more than 1e-9 mm. Where several
// triangles give the same z (shared edges and vertices), the lowest-numbered one is reported, so
// the whole CLPoint is the same whatever the order triangles are tried in (a hint, the index, the
// brute force).
#include "millnet/tooling/cutter.hpp"
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
  Eigen::Vector3d cc = Eigen::Vector3d::Zero();  ///< cutter-contact point on the mesh
  std::int32_t triangle = -1;                    ///< index of the touched triangle
};

/// tooling::Cutter::check, and a drill refused (it has no finishing shape). Throws millnet::Error.
void check_finishing_cutter(const tooling::Cutter& cutter);

class DropCutter {
public:
  /// Builds the index: O(#F). Throws millnet::Error for an invalid mesh or cutter.
  DropCutter(const ingest::Mesh& mesh, const tooling::Cutter& cutter);
  ~DropCutter();
  DropCutter(DropCutter&&) noexcept;
  DropCutter& operator=(DropCutter&&) noexcept;

  [[nodiscard]] const tooling::Cutter& cutter() const;
  /// One query: O(triangles whose grown XY box contains (x, y)).
  [[nodiscard]] CLPoint drop(double x, double y) const;
  /// The same query started from triangle `hint` (a neighbouring query's contact; −1 for none):
  /// the same z, found sooner when the hint is the contact or near it.
  [[nodiscard]] CLPoint drop(double x, double y, std::int32_t hint) const;
  /// Many queries, OpenMP over fixed blocks of 256 points (each block starts its next query from
  /// the previous point's contact triangle), results identical for any thread count.
  [[nodiscard]] std::vector<CLPoint> drop(const std::vector<Eigen::Vector2d>& xy) const;
  /// Tip heights on a grid x = x0 + j·step, y = y0 + i·step (row-major, rows = y), -infinity where
  /// nothing lies under the cutter. OpenMP over rows; identical for any thread count. Throws
  /// millnet::Error for nx or ny < 0 or a non-finite origin or step.
  [[nodiscard]] std::vector<double> drop_grid(double x0, double y0, double step, int nx, int ny) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The reference: every triangle tested, no index. O(#F) per query; for tests and benchmarks. The
/// mesh is not validated (indices must be in range).
[[nodiscard]] CLPoint drop_brute_force(const ingest::Mesh& mesh, const tooling::Cutter& cutter, double x, double y);

}  // namespace millnet::finish
