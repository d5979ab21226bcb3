#pragma once
// The gouge oracle of the roughing tests (test_rough, test_app's CLI contract): the exact maximum of
// a mesh's triangles under the tool disk, and a replay of a written program against it. Independent
// of the planner, the pocket module and the ingest z-buffer.
#include "testing/gcode_replay.hpp"

#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace millnet::testing {

namespace gouge_detail {
inline constexpr double kPi = 3.14159265358979323846;
}

// ---------------------------------------------------------------------------------------------
// The gouge oracle: the exact maximum height of the mesh's triangles under a disk.

/// Brute force over the mesh triangles (bucketed in XY only to find the candidates): the maximum z
/// of a triangle over a closed disk is the max of a linear function over a convex set, attained at
/// a triangle vertex inside the disk, at an edge–circle intersection, or at the circle point in
/// the direction of the plane's gradient when it lies inside the triangle (the centre when flat).
/// Vertical triangles: vertices and edge–circle intersections (exact as well).
class TopOracle {
public:
  explicit TopOracle(const ingest::Mesh& m, double cell = 2.0) : cell_(cell) {
    x0_ = m.V.col(0).minCoeff() - 1;
    y0_ = m.V.col(1).minCoeff() - 1;
    nx_ = static_cast<int>((m.V.col(0).maxCoeff() + 1 - x0_) / cell_) + 1;
    ny_ = static_cast<int>((m.V.col(1).maxCoeff() + 1 - y0_) / cell_) + 1;
    zmax_ = m.V.col(2).maxCoeff();
    buckets_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
    // O(#F · cells per triangle).
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      Tri t;
      for (Eigen::Index k = 0; k < 3; ++k) t.v[static_cast<std::size_t>(k)] = m.V.row(m.F(f, k)).transpose();
      t.lo = t.v[0].head<2>().cwiseMin(t.v[1].head<2>()).cwiseMin(t.v[2].head<2>());
      t.hi = t.v[0].head<2>().cwiseMax(t.v[1].head<2>()).cwiseMax(t.v[2].head<2>());
      t.zmax = std::max({t.v[0].z(), t.v[1].z(), t.v[2].z()});
      const Eigen::Vector2d e1 = (t.v[1] - t.v[0]).head<2>(), e2 = (t.v[2] - t.v[0]).head<2>();
      t.det = e1.x() * e2.y() - e1.y() * e2.x();
      t.flat_xy = std::abs(t.det) <= 1e-12 * std::max(1.0, e1.squaredNorm() + e2.squaredNorm());
      if (!t.flat_xy) {
        // z = v0.z + g·(p − v0) on the plane.
        const double dz1 = t.v[1].z() - t.v[0].z(), dz2 = t.v[2].z() - t.v[0].z();
        t.g = Eigen::Vector2d((dz1 * e2.y() - dz2 * e1.y()) / t.det, (dz2 * e1.x() - dz1 * e2.x()) / t.det);
      }
      const std::size_t id = tris_.size();
      tris_.push_back(t);
      for (int i = cy(t.lo.y()); i <= cy(t.hi.y()); ++i)
        for (int j = cx(t.lo.x()); j <= cx(t.hi.x()); ++j) buckets_[idx(i, j)].push_back(id);
    }
    stamp_.assign(tris_.size(), 0);
  }

  [[nodiscard]] double zmax() const { return zmax_; }

  /// Max z of the surface over the closed disk (c, r), considering only triangles that reach above
  /// `floor`; returns −∞ when none does. O(triangles in the disk's buckets).
  double max_over_disk(const Eigen::Vector2d& c, double r, double floor = -std::numeric_limits<double>::infinity()) {
    ++cur_;
    double best = -std::numeric_limits<double>::infinity();
    for (int i = cy(c.y() - r); i <= cy(c.y() + r); ++i)
      for (int j = cx(c.x() - r); j <= cx(c.x() + r); ++j)
        for (const std::size_t id : buckets_[idx(i, j)]) {
          if (stamp_[id] == cur_) continue;
          stamp_[id] = cur_;
          const Tri& t = tris_[id];
          if (t.zmax <= floor || t.zmax <= best) continue;
          if (c.x() + r < t.lo.x() || c.x() - r > t.hi.x() || c.y() + r < t.lo.y() || c.y() - r > t.hi.y()) continue;
          best = std::max(best, tri_max(t, c, r));
        }
    return best;
  }

private:
  struct Tri {
    std::array<Eigen::Vector3d, 3> v;
    Eigen::Vector2d lo, hi, g = Eigen::Vector2d::Zero();
    double zmax = 0, det = 0;
    bool flat_xy = false;
  };

  static double tri_max(const Tri& t, const Eigen::Vector2d& c, double r) {
    double best = -std::numeric_limits<double>::infinity();
    const double r2 = r * r;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& a = t.v[static_cast<std::size_t>(k)];
      const Eigen::Vector3d& b = t.v[static_cast<std::size_t>((k + 1) % 3)];
      if ((a.head<2>() - c).squaredNorm() <= r2) best = std::max(best, a.z());
      // |a + s(b − a) − c|² = r², s ∈ [0, 1].
      const Eigen::Vector2d d = (b - a).head<2>(), f = a.head<2>() - c;
      const double A = d.squaredNorm();
      if (A <= 0) continue;
      const double B = 2 * f.dot(d), C = f.squaredNorm() - r2, disc = B * B - 4 * A * C;
      if (disc < 0) continue;
      for (const double s : {(-B - std::sqrt(disc)) / (2 * A), (-B + std::sqrt(disc)) / (2 * A)})
        if (s >= 0 && s <= 1) best = std::max(best, a.z() + s * (b.z() - a.z()));
    }
    if (!t.flat_xy) {
      const double gn = t.g.norm();
      const Eigen::Vector2d q = gn > 0 ? Eigen::Vector2d(c + r * t.g / gn) : c;
      const Eigen::Vector2d e1 = (t.v[1] - t.v[0]).head<2>(), e2 = (t.v[2] - t.v[0]).head<2>(),
                            w = q - t.v[0].head<2>();
      const double u = (w.x() * e2.y() - w.y() * e2.x()) / t.det, v = (e1.x() * w.y() - e1.y() * w.x()) / t.det;
      if (u >= 0 && v >= 0 && u + v <= 1) best = std::max(best, t.v[0].z() + t.g.dot(w));
    }
    return best;
  }
  int cx(double x) const { return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1); }
  int cy(double y) const { return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1); }
  std::size_t idx(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(j);
  }

  double cell_, x0_ = 0, y0_ = 0, zmax_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<Tri> tris_;
  std::vector<std::vector<std::size_t>> buckets_;
  std::vector<unsigned> stamp_;
  unsigned cur_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The gouge replay of the written G-code.

struct GougeReport {
  long samples = 0, checked = 0, near = 0, violations = 0;
  double worst_depth = 0, worst_radial = 0;
  std::string first, worst;
  double min_z = 0;
};

/// Samples every feed move (G1/G2/G3; arcs on the circle, helices linear in Z) at ≤ step mm and,
/// at each sample, asserts that the surface under the flat end mill's disk (radius R − 0.001 mm:
/// the 4-decimal rounding of the program) stays at or below tool Z − stock_to_leave + tol.
/// `stock_top` converts G-code Z (0 = stock top) to the part frame. Also counts "near" samples:
/// where a disk 1 mm larger would reach material above the tool tip (the check is not vacuous).
inline GougeReport replay_against_mesh(const std::string& gcode, const ingest::Mesh& part, double stock_top, double R,
                                       double stl, double safe_z, double step = 0.1, double tol = 0.005,
                                       bool include_rapids = false) {
  const auto rep = millnet::testing::replay_gcode(gcode, safe_z);
  TopOracle oracle(part);
  GougeReport g;
  g.min_z = rep.min_z;
  const double r = R - 0.001;
  auto check = [&](const Eigen::Vector2d& c, double z_gcode, int line) {
    ++g.samples;
    const double z_part = z_gcode + stock_top;
    const double allowed = z_part - stl + tol;   // the surface may reach up to here under the disk
    if (allowed - 1.0 >= oracle.zmax()) return;  // far above the whole part
    ++g.checked;
    if (oracle.max_over_disk(c, r + 1.0, allowed) > allowed) ++g.near;
    const double top = oracle.max_over_disk(c, r, allowed);
    if (!(top > allowed)) return;
    ++g.violations;
    const double depth = top - (z_part - stl);
    // Radial intrusion: the largest disk radius that stays clear, by bisection.
    double lo = 0, hi = r;
    if (oracle.max_over_disk(c, 0, allowed) > allowed) hi = lo = 0;
    for (int it = 0; it < 40 && hi - lo > 1e-5; ++it) {
      const double mid = 0.5 * (lo + hi);
      (oracle.max_over_disk(c, mid, allowed) > allowed ? hi : lo) = mid;
    }
    const double radial = r - lo;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "line %d: tool at (%.4f, %.4f) Z %.4f (part z %.4f, level Z %.3f): surface %.4f under the disk, "
                  "%.4f mm too deep, %.4f mm radially into the part",
                  line, c.x(), c.y(), z_gcode, z_part, z_gcode, top, depth, radial);
    if (g.first.empty()) g.first = buf;
    if (depth > g.worst_depth) {
      g.worst_depth = depth;
      g.worst = buf;
    }
    g.worst_radial = std::max(g.worst_radial, radial);
  };
  for (const auto& mv : rep.moves) {
    if (mv.g == 0 && !include_rapids) continue;
    const Eigen::Vector2d a(mv.from[0], mv.from[1]), b(mv.to[0], mv.to[1]);
    if (mv.g <= 1) {
      const double len = std::max((b - a).norm(), std::abs(mv.to[2] - mv.from[2]));
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        check(a + t * (b - a), mv.from[2] + t * (mv.to[2] - mv.from[2]), mv.line);
      }
      continue;
    }
    const Eigen::Vector2d c(mv.center[0], mv.center[1]);
    const double r0 = (a - c).norm(), r1 = (b - c).norm();
    const double a0 = std::atan2(a.y() - c.y(), a.x() - c.x()), a1 = std::atan2(b.y() - c.y(), b.x() - c.x());
    double sw = a1 - a0;
    if (mv.g == 3) {
      while (sw <= 1e-12) sw += 2 * gouge_detail::kPi;
    } else {
      while (sw >= -1e-12) sw -= 2 * gouge_detail::kPi;
    }
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sw) * std::max(r0, r1) / step)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n, ang = a0 + t * sw, rr = r0 + t * (r1 - r0);
      check(c + rr * Eigen::Vector2d(std::cos(ang), std::sin(ang)), mv.from[2] + t * (mv.to[2] - mv.from[2]), mv.line);
    }
  }
  return g;
}

}  // namespace millnet::testing
