// The finishing tool of a part by its size and concave radius (tool_choice.hpp).
#include "millnet/job/tool_choice.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>

namespace millnet::job {
namespace {

/// Faces whose normal's Z is above this face up.
constexpr double kUpNz = 1e-3;
/// Faces whose normal's Z is below this are steeper than kSteepestFaceRad.
const double kWallNz = std::cos(kSteepestFaceRad);

struct Edge {
  std::int32_t a, b;  ///< vertex indices, a < b
  std::int32_t face;
  std::int32_t opposite;  ///< the face's third vertex
  bool operator<(const Edge& o) const { return std::tie(a, b, face) < std::tie(o.a, o.b, o.face); }
};

Eigen::Vector3d vertex(const ingest::Mesh& m, std::int32_t i) { return m.V.row(i).transpose(); }

/// Unit normal of face f (zero for a degenerate face).
Eigen::Vector3d normal(const ingest::Mesh& m, Eigen::Index f) {
  const Eigen::Vector3d n =
      (vertex(m, m.F(f, 1)) - vertex(m, m.F(f, 0))).cross(vertex(m, m.F(f, 2)) - vertex(m, m.F(f, 0)));
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

/// Distance of p from the line through a along the unit direction e.
double from_line(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& e) {
  const Eigen::Vector3d d = p - a;
  return (d - d.dot(e) * e).norm();
}

}  // namespace

PartShape part_shape(const ingest::Mesh& mesh, double stock_top) {
  PartShape s;
  s.concave_radius_mm = std::numeric_limits<double>::infinity();
  const Eigen::Index F = mesh.F.rows();
  if (F == 0) return s;
  s.size_mm = std::max(mesh.V.col(0).maxCoeff() - mesh.V.col(0).minCoeff(),
                       mesh.V.col(1).maxCoeff() - mesh.V.col(1).minCoeff());
  std::vector<Eigen::Vector3d> n(static_cast<std::size_t>(F));
  double lowest_up = std::numeric_limits<double>::infinity();
  std::vector<Edge> edges;
  edges.reserve(static_cast<std::size_t>(3 * F));
  for (Eigen::Index f = 0; f < F; ++f) {  // O(F)
    n[static_cast<std::size_t>(f)] = normal(mesh, f);
    if (n[static_cast<std::size_t>(f)].z() > kUpNz)
      for (int k = 0; k < 3; ++k) lowest_up = std::min(lowest_up, mesh.V(mesh.F(f, k), 2));
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = mesh.F(f, k), v = mesh.F(f, (k + 1) % 3), w = mesh.F(f, (k + 2) % 3);
      edges.push_back({std::min(u, v), std::max(u, v), static_cast<std::int32_t>(f), w});
    }
  }
  s.depth_mm = std::isfinite(lowest_up) ? std::max(0.0, stock_top - lowest_up) : 0.0;
  std::sort(edges.begin(), edges.end());  // O(F log F): an edge's faces side by side

  std::vector<std::pair<double, double>> radius_length;  // (R, edge length) of concave curved edges
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {   // O(F)
    const Edge& e1 = edges[i];
    const Edge& e2 = edges[i + 1];
    if (e1.a != e2.a || e1.b != e2.b) continue;
    if (i + 2 < edges.size() && edges[i + 2].a == e1.a && edges[i + 2].b == e1.b) continue;  // non-manifold
    const Eigen::Vector3d& n1 = n[static_cast<std::size_t>(e1.face)];
    const Eigen::Vector3d& n2 = n[static_cast<std::size_t>(e2.face)];
    if (std::min(n1.z(), n2.z()) < kWallNz) continue;  // a wall, or not machined from above
    const double theta = std::atan2(n1.cross(n2).norm(), n1.dot(n2));
    if (theta < kFlatEdgeRad || theta > kSharpConcaveRad) continue;
    const Eigen::Vector3d a = vertex(mesh, e1.a), b = vertex(mesh, e1.b);
    const double length = (b - a).norm();
    if (!(length > 0)) continue;
    const Eigen::Vector3d dir = (b - a) / length;
    const Eigen::Vector3d p1 = vertex(mesh, e1.opposite), p2 = vertex(mesh, e2.opposite);
    if ((p2 - p1).dot(n2 - n1) >= 0) continue;  // the normals diverge: convex
    // The faces' widths across the edge (a cylinder's facets: the chord between generators).
    const double width = 0.5 * (from_line(p1, a, dir) + from_line(p2, a, dir));
    radius_length.emplace_back(width / (2 * std::sin(theta / 2)), length);
  }
  double total = 0;
  for (const auto& [r, l] : radius_length) total += l;
  s.concave_edges_mm = total;
  if (radius_length.empty()) return s;
  std::sort(radius_length.begin(), radius_length.end());  // O(E log E)
  double below = 0;
  for (const auto& [r, l] : radius_length) {  // the radius at the kRestShare quantile of length
    below += l;
    if (below > kRestShare * total) {
      s.concave_radius_mm = r;
      break;
    }
  }
  return s;
}

const tooling::Tool* finishing_ball(const std::vector<tooling::Tool>& library, const PartShape& shape) {
  const double largest = std::min(shape.size_mm / kSizePerDiameter, 2 * shape.concave_radius_mm);
  auto reaches = [&](const tooling::Tool& t) { return t.stickout_mm <= 0 || t.stickout_mm >= shape.depth_mm; };
  const tooling::Tool *fits = nullptr, *smallest = nullptr, *longest = nullptr;
  for (const tooling::Tool& t : library) {  // O(tools)
    if (t.type != tooling::ToolType::Ball) continue;
    auto shorter = [&](const tooling::Tool* than) { return t.stickout_mm < than->stickout_mm; };
    if (longest == nullptr ||
        (longest->stickout_mm > 0 && (t.stickout_mm <= 0 || t.stickout_mm > longest->stickout_mm)))
      longest = &t;
    if (!reaches(t)) continue;
    if (smallest == nullptr || t.diameter_mm < smallest->diameter_mm ||
        (t.diameter_mm == smallest->diameter_mm && shorter(smallest)))
      smallest = &t;
    if (t.diameter_mm <= largest &&
        (fits == nullptr || t.diameter_mm > fits->diameter_mm || (t.diameter_mm == fits->diameter_mm && shorter(fits))))
      fits = &t;
  }
  return fits != nullptr ? fits : smallest != nullptr ? smallest : longest;
}

}  // namespace millnet::job
