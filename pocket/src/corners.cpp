// Corner blending of a tool-centre polyline (smoothing.hpp, blend_corners).
#include "millnet/pocket/smoothing.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "geometry_internal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::pocket {

namespace {
constexpr double kStraightRad = 1e-9;  ///< a turn this small is straight on
constexpr double kReversalRad = std::numbers::pi - 1e-6;
constexpr int kHalvings = 4;

using detail::cross;

/// Appends v, or gives its bulge to the last vertex when v coincides with it.
void push(std::vector<Vertex>& out, const Vec2& p, double bulge) {
  if (!out.empty() && (out.back().p() - p).norm() <= tol::join_mm) {
    out.back().bulge = bulge;
    return;
  }
  out.push_back({p.x(), p.y(), bulge});
}
}  // namespace

std::vector<Vertex> blend_corners(const std::vector<Vec2>& pts, const std::vector<char>& blendable,
                                  const CornerBlendParams& params, const MoveOk& move_ok, CornerBlendStats* stats) {
  if (blendable.size() != pts.size()) throw Error("blend_corners: one blendable flag per point expected");
  if (!(params.max_radius_mm >= 0) || !(params.max_deviation_mm >= 0) || !(params.min_radius_mm > 0) ||
      !(params.clearance_mm > 0))
    throw Error("blend_corners: radii and deviation must be ≥ 0, min radius and clearance > 0");
  CornerBlendStats st;
  std::vector<Vertex> out;
  if (pts.empty()) return out;
  out.push_back({pts.front().x(), pts.front().y(), 0.0});
  // The polyline with repeated points removed: each kept point with its flag.
  std::vector<Vec2> p{pts.front()};
  std::vector<char> flag{0};
  for (std::size_t k = 1; k < pts.size(); ++k) {
    if ((pts[k] - p.back()).norm() <= tol::join_mm) continue;
    p.push_back(pts[k]);
    flag.push_back(blendable[k]);
  }
  flag.back() = 0;
  const double t_cap = 0.99 * std::sqrt(3.0) * params.clearance_mm;
  // `from` is where the path stands before the corner's incoming segment, i.e. the last output
  // vertex; the incoming segment is still p[k − 1] → p[k] (half of it at most is used by a blend).
  std::size_t k = 1;
  std::vector<Vec2> q{p.front()};  // p without straight-on vertices
  std::vector<char> qf{0};
  for (; k < p.size(); ++k) {
    if (k + 1 < p.size()) {
      const Vec2 u = (p[k] - q.back()).normalized(), w = (p[k + 1] - p[k]).normalized();
      if (std::atan2(std::abs(cross(u, w)), u.dot(w)) < kStraightRad) {
        ++st.merged;
        continue;
      }
    }
    q.push_back(p[k]);
    qf.push_back(flag[k]);
  }
  for (k = 1; k + 1 < q.size(); ++k) {
    const Vec2 &A = q[k - 1], &P = q[k], &B = q[k + 1];
    const double la = (P - A).norm(), lb = (B - P).norm();
    const Vec2 u = (P - A) / la, w = (B - P) / lb;
    const double phi = std::atan2(std::abs(cross(u, w)), u.dot(w));
    ++st.corners;
    bool done = false;
    if (qf[k] && phi < kReversalRad) {
      const double tan_half = std::tan(phi / 2);
      const double dev_per_r = 1 / std::cos(phi / 2) - 1;
      double r = params.max_radius_mm;
      r = std::min(r, std::min({0.5 * la, 0.5 * lb, t_cap}) / tan_half);
      if (dev_per_r > 0) r = std::min(r, params.max_deviation_mm / dev_per_r);
      for (int h = 0; h <= kHalvings && r >= params.min_radius_mm; ++h, r *= 0.5) {
        const double t = r * tan_half;
        const Vec2 a = P - t * u, b = P + t * w;
        if (!move_ok(a, b)) continue;
        push(out, a, (cross(u, w) > 0 ? 1.0 : -1.0) * std::tan(phi / 4));
        push(out, b, 0.0);
        ++st.blended;
        done = true;
        break;
      }
    }
    if (!done) push(out, P, 0.0);
  }
  if (q.size() > 1) push(out, q.back(), 0.0);
  if (stats != nullptr) *stats = st;
  return out;
}

}  // namespace millnet::pocket
