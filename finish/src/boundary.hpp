#pragma once
// Internal to finish/: the machining boundary (FinishParams::boundary) as a test on CL points, and
// the clipping of passes to it.
#include "sampling.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace millnet::finish::detail {

/// The machining boundary of one plan: the polygons (even-odd), the part's silhouette (a grid of
/// the XY projections of its non-vertical faces) and the tip's Z range.
class Fence {
public:
  /// Builds the silhouette's grid when boundary.on_part: O(F + grid entries), the grid sized so that
  /// its entries stay within a few times the face count. Throws millnet::Error for a polygon of
  /// fewer than 3 points or a non-finite coordinate, or z_min > z_max.
  Fence(const ingest::Mesh& mesh, const Boundary& boundary);

  /// Whether anything is tested (false: every point is inside).
  [[nodiscard]] bool active() const { return active_; }
  [[nodiscard]] bool inside_xy(double x, double y) const;
  [[nodiscard]] bool inside(const Eigen::Vector3d& p) const {
    return p.z() >= z_min_ && p.z() <= z_max_ && inside_xy(p.x(), p.y());
  }

  /// The pieces of the lines inside, in order. A line that leaves is cut at the crossing on the
  /// segment that leaves (bisection to tol::boundary_crossing_mm: a point of the planned segment)
  /// and starts again at the crossing where it comes back; a closed loop cut open is rejoined across
  /// its start (one piece, not two). Pieces shorter than tol::min_pass_mm are dropped. A segment
  /// whose ends are inside is kept whole (segments are CL sampling steps here, ≤ 0.25 mm).
  /// O(points · log(step / tol)), the lines in parallel.
  [[nodiscard]] std::vector<std::vector<Sample>> clip(std::vector<std::vector<Sample>> lines) const;

private:
  struct Triangle {
    std::array<Eigen::Vector2d, 3> v;  ///< counter-clockwise
  };
  [[nodiscard]] bool over_part(double x, double y) const;
  [[nodiscard]] bool in_polygons(double x, double y) const;
  [[nodiscard]] Sample crossing(const Sample& in, const Sample& out) const;
  /// clip() of one line.
  [[nodiscard]] std::vector<std::vector<Sample>> clip_line(std::vector<Sample> line) const;

  bool active_ = false;
  Boundary boundary_;  ///< its polygons (the rest is kept below)
  double z_min_, z_max_;
  bool on_part_ = false;
  std::vector<Triangle> tris_;
  double gx0_ = 0, gy0_ = 0, cell_ = 1;
  std::size_t nx_ = 0, ny_ = 0;
  std::vector<std::size_t> start_;  ///< CSR: cell c lists ids_[start_[c] .. start_[c + 1])
  std::vector<std::uint32_t> ids_;
};

}  // namespace millnet::finish::detail
