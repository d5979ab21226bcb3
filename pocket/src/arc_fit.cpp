// Arc fitting of tool paths (arc_fit.hpp).
#include "arc_fit.hpp"

#include "millnet/pocket/tolerances.hpp"

#include "geometry_internal.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace millnet::pocket {

namespace {

/// Larger radii are written as lines: a G2/G3 centre metres away is no better than the chord, and
/// its I/J lose the digits that place the arc.
constexpr double kMaxArcRadiusMm = 1000;

using detail::cross;

struct Fit {
  double bulge = 0;
};

/// The arc from pts[i] to pts[j] through pts[(i+j)/2], if every vertex between lies within tol of
/// its circle, each chord's sagitta is within tol, the vertices advance one way round the centre by
/// less than 180° in all, and (with walls) the arc keeps the clearance. O(j − i) + the samples.
std::optional<Fit> fit(const std::vector<Vertex>& pts, std::size_t i, std::size_t j, double tol,
                       const Clearance* walls) {
  const Vec2 a = pts[i].p(), m = pts[(i + j) / 2].p(), b = pts[j].p();
  const Vec2 ab = m - a, ac = b - a;
  const double d = 2 * cross(ab, ac);
  const double scale = ab.squaredNorm() + ac.squaredNorm();
  if (!(std::abs(d) > 1e-12 * scale)) return std::nullopt;  // collinear (or degenerate)
  const Vec2 c = a + Vec2(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                          ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm()) /
                         d;
  const double r = (a - c).norm();
  if (!(r <= kMaxArcRadiusMm)) return std::nullopt;
  const double dir = d > 0 ? 1.0 : -1.0;  // CCW when > 0
  double sweep = 0;
  for (std::size_t k = i; k <= j; ++k) {
    const Vec2 u = pts[k].p() - c;
    if (std::abs(u.norm() - r) > tol) return std::nullopt;
    if (k == j) break;
    const Vec2 v = pts[k + 1].p() - c;
    const double step = std::atan2(cross(u, v), u.dot(v));
    if (!(step * dir > 0) || std::abs(step) >= M_PI / 2) return std::nullopt;
    sweep += step;
    const double half = 0.5 * (pts[k + 1].p() - pts[k].p()).norm();
    if (r - std::sqrt(std::max(0.0, r * r - half * half)) > tol) return std::nullopt;
  }
  if (std::abs(sweep) >= M_PI) return std::nullopt;  // |bulge| < 1: one G2/G3 of at most a half turn
  if (walls) {
    const double a0 = std::atan2(a.y() - c.y(), a.x() - c.x());
    const int n = std::max(8, static_cast<int>(std::ceil(std::abs(sweep) * r / tol::arc_fit_sample_mm)));
    for (int s = 1; s < n; ++s) {  // the ends are the input's own vertices
      const double t = a0 + sweep * s / n;
      if (walls->wall_distance(c + r * Vec2(std::cos(t), std::sin(t))) < walls->clearance() - tol::clear_mm)
        return std::nullopt;
    }
  }
  return Fit{std::tan(sweep / 4)};
}

}  // namespace

std::vector<Vertex> fit_arcs(const std::vector<Vertex>& pts, double tol_mm, const Clearance* walls) {
  std::vector<Vertex> out;
  out.reserve(pts.size());
  std::size_t i = 0;
  const std::size_t n = pts.size();
  while (i < n) {
    if (i + 1 == n) {
      out.push_back(pts[i]);
      break;
    }
    // The straight run from i: segments i … end−1 are lines.
    std::size_t end = i;
    while (end + 1 < n && pts[end].bulge == 0.0) ++end;
    std::size_t ok = 0;
    std::optional<Fit> best;
    if (end >= i + kMinArcSegments) {
      if (auto f = fit(pts, i, i + kMinArcSegments, tol_mm, walls)) {
        ok = i + kMinArcSegments;
        best = f;
        // Grow by doubling while the fit holds, then bisect between the last good and first bad end.
        std::size_t step = kMinArcSegments, bad = end + 1;
        while (ok + step <= end) {
          if (auto g = fit(pts, i, ok + step, tol_mm, walls)) {
            ok += step;
            best = g;
            step *= 2;
          } else {
            bad = ok + step;
            break;
          }
        }
        if (bad == end + 1 && ok < end) {  // ran past the run's end: try the end itself
          if (auto g = fit(pts, i, end, tol_mm, walls)) {
            ok = end;
            best = g;
          } else {
            bad = end;
          }
        }
        while (bad > ok + 1 && bad <= end) {
          const std::size_t mid = ok + (bad - ok) / 2;
          if (auto g = fit(pts, i, mid, tol_mm, walls)) {
            ok = mid;
            best = g;
          } else {
            bad = mid;
          }
        }
      }
    }
    if (best) {
      out.push_back({pts[i].x, pts[i].y, best->bulge});
      i = ok;
    } else {
      out.push_back(pts[i]);
      ++i;
    }
  }
  return out;
}

std::size_t fit_arcs(Path2D& path, double tol_mm, const Clearance* walls) {
  std::size_t arcs = 0;
  for (Chain& c : path.chains) {  // O(n log n) per chain
    std::size_t before = 0;
    for (const Vertex& v : c.pts) before += v.bulge != 0.0;
    c.pts = fit_arcs(c.pts, tol_mm, walls);
    c.feed.clear();
    std::size_t after = 0;
    for (const Vertex& v : c.pts) after += v.bulge != 0.0;
    arcs += after - before;
  }
  return arcs;
}

}  // namespace millnet::pocket
