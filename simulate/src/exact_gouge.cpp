// The exact gouge check (exact_gouge.hpp): distances from the cutter's core to the part solid
// (the prisms below the design's triangles), swept along moves by a Lipschitz branch and bound,
// and the z-map's gouge places confirmed or refuted with it.
#include "millnet/simulate/exact_gouge.hpp"

#include "metrics_internal.hpp"

#include "millnet/core/error.hpp"
#include "millnet/simulate/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <variant>

namespace millnet::simulate {

namespace {

using P3 = gcode::Point3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Distances are looked for this far beyond the cutter's reach (mm): a clearance that large is
/// reported as such, which lets the branch and bound drop whole moves that pass far from the part.
constexpr double kProbeMarginMm = 0.5;
/// A move is evaluated at most this many times (a backstop; the resolution bounds it first).
constexpr std::size_t kMaxEvaluationsPerSegment = 200000;

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const P3& a) { return std::sqrt(dot(a, a)); }
P3 lerp(const P3& a, const P3& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

double point_segment_distance(const P3& p, const P3& a, const P3& b) {
  const P3 ab = sub(b, a);
  const double l2 = dot(ab, ab);
  const double t = l2 > 0 ? std::clamp(dot(sub(p, a), ab) / l2, 0.0, 1.0) : 0.0;
  return norm(sub(p, lerp(a, b, t)));
}

// Distance from p to the triangle abc (closest-point regions, Ericson, Real-Time Collision
// Detection §5.1.5); a degenerate triangle is its three edges.
double point_triangle_distance(const P3& p, const P3& a, const P3& b, const P3& c) {
  const P3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const P3 n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
  if (dot(n, n) <= 1e-24)
    return std::min(
        {point_segment_distance(p, a, b), point_segment_distance(p, b, c), point_segment_distance(p, a, c)});
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(ap);
  const P3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return point_segment_distance(p, a, b);
  const P3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return point_segment_distance(p, a, c);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return point_segment_distance(p, b, c);
  return std::abs(dot(ap, n)) / std::sqrt(dot(n, n));  // inside the face's region: to its plane
}

// sqrt(x² + y²): the lengths here are millimetres, far from hypot's overflow and underflow guards
// (which cost more than the rest of a probe).
double root_sum_sq(double x, double y) { return std::sqrt(x * x + y * y); }

// Distance in a plane from (u, v) to the segment (0, za)–(L, zb).
double segment_distance_2d(double u, double v, double L, double za, double zb) {
  const double du = L, dv = zb - za;
  const double t = std::clamp((u * du + (v - za) * dv) / (du * du + dv * dv), 0.0, 1.0);
  return root_sum_sq(u - t * du, v - (za + t * dv));
}

// Distance from p to the vertical strip below the edge ab (down to −∞): in the strip's plane,
// the region under the edge between the verticals through a and b; across it, the plane distance.
double strip_distance(const P3& p, const P3& a, const P3& b) {
  const double hx = b[0] - a[0], hy = b[1] - a[1], L = root_sum_sq(hx, hy);
  if (L <= tol::xy_length_mm) {  // a vertical edge: the ray below its higher end
    return root_sum_sq(root_sum_sq(p[0] - a[0], p[1] - a[1]), std::max(0.0, p[2] - std::max(a[2], b[2])));
  }
  const double ux = hx / L, uy = hy / L;
  const double u = (p[0] - a[0]) * ux + (p[1] - a[1]) * uy;
  const double w = -(p[0] - a[0]) * uy + (p[1] - a[1]) * ux;
  double d2 = 0;
  const bool under = u >= 0 && u <= L && p[2] <= a[2] + (b[2] - a[2]) * u / L;
  if (!under) {
    d2 = std::min({segment_distance_2d(u, p[2], L, a[2], b[2]), root_sum_sq(u, std::max(0.0, p[2] - a[2])),
                   root_sum_sq(u - L, std::max(0.0, p[2] - b[2]))});
  }
  return root_sum_sq(w, d2);
}

// The height of the triangle's plane over (x, y) when (x, y) lies in its XY projection (edges
// included); NaN outside it and for a vertical triangle.
double height_over(const std::array<P3, 3>& t, double x, double y) {
  const double ax = t[0][0], ay = t[0][1];
  const double e1x = t[1][0] - ax, e1y = t[1][1] - ay, e2x = t[2][0] - ax, e2y = t[2][1] - ay;
  const double det = e1x * e2y - e1y * e2x;
  if (std::abs(det) <= 2 * tol::exact_vertical_area_mm2) return kNaN;
  const double px = x - ax, py = y - ay;
  const double s = (px * e2y - py * e2x) / det, r = (e1x * py - e1y * px) / det;
  constexpr double kEdge = 1e-12;  // barycentric slack: a point on a shared edge is in both
  if (s < -kEdge || r < -kEdge || s + r > 1 + kEdge) return kNaN;
  return t[0][2] + s * (t[1][2] - t[0][2]) + r * (t[2][2] - t[0][2]);
}

/// The core of a cutter: sample offsets from the tip (dx, dy, dz) and the ball radius around them.
struct Core {
  std::vector<P3> samples;
  double rc = 0;     ///< radius of the ball swept around every sample
  double reach = 0;  ///< the disk's radius (0 for a ball)
};

Core core_of(const tooling::Cutter& cutter) {
  cutter.check();
  Core k;
  const double R = cutter.radius();
  const tooling::CutterType shape = cutter.shape();
  if (shape == tooling::CutterType::Ball) {
    k.rc = R;
    k.samples.push_back({0, 0, R});
    return k;
  }
  k.rc = shape == tooling::CutterType::Bull ? cutter.profile_corner_radius() : 0.0;
  const double rmax = shape == tooling::CutterType::Bull ? R - k.rc : R - tol::exact_rim_inset_mm;
  k.reach = std::max(0.0, rmax);
  const int rings =
      std::clamp(static_cast<int>(std::ceil(rmax / tol::exact_disk_step_mm)), 1, tol::exact_disk_max_rings);
  const double step = rmax / rings;
  k.samples.push_back({0, 0, k.rc + cutter.profile_height(0)});
  for (int i = 1; i <= rings; ++i) {  // O(rings²) samples
    const double r = step * i;
    const int n = std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * r / std::max(step, 1e-9))));
    const double dz = shape == tooling::CutterType::Bull ? k.rc : cutter.profile_height(r);
    for (int j = 0; j < n; ++j) {
      const double th = 2 * std::numbers::pi * j / n;
      k.samples.push_back({r * std::cos(th), r * std::sin(th), dz});
    }
  }
  return k;
}

double core_penetration(const PartSolid& part, const Core& k, const P3& tip) {
  const double reach = k.rc + kProbeMarginMm;
  if (k.samples.size() > 1) {  // the whole disk is clear when its centre is far enough from the part
    const P3 c{tip[0], tip[1], tip[2] + k.samples[0][2]};
    const PartSolid::Probe pc = part.probe(c, reach + k.reach);
    if (!pc.inside && pc.distance - k.reach > reach) return k.rc - (pc.distance - k.reach);
  }
  double best = -std::numeric_limits<double>::infinity();
  for (const P3& s : k.samples) {  // O(samples · probe)
    const PartSolid::Probe q = part.probe({tip[0] + s[0], tip[1] + s[1], tip[2] + s[2]}, reach);
    best = std::max(best, q.inside ? k.rc + q.depth_below_top : k.rc - q.distance);
  }
  return best;
}

bool known_point(const P3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// The polyline a move follows from `start` (arcs: chords of sagitta ≤ chord_tol).
std::vector<P3> move_points(const gcode::Move& mv, const P3& start, const P3& end, double chord_tol) {
  if (mv.motion != gcode::Motion::ArcCW && mv.motion != gcode::Motion::ArcCCW) return {start, end};
  const double cx = mv.center[0], cy = mv.center[1];
  const double r0 = std::hypot(start[0] - cx, start[1] - cy), r1 = std::hypot(end[0] - cx, end[1] - cy);
  if (r0 <= tol::min_arc_radius_mm) return {start, end};
  const double a0 = std::atan2(start[1] - cy, start[0] - cx), a1 = std::atan2(end[1] - cy, end[0] - cx);
  const double dir = mv.motion == gcode::Motion::ArcCCW ? 1.0 : -1.0;
  double sweep = std::fmod(dir * (a1 - a0) + 4 * std::numbers::pi, 2 * std::numbers::pi);
  if (sweep <= tol::full_circle_rad) sweep = 2 * std::numbers::pi;
  const double rmax = std::max(r0, r1);
  const double max_step = chord_tol < rmax ? 2 * std::acos(1 - chord_tol / rmax) : std::numbers::pi / 2;
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(sweep / max_step)));
  std::vector<P3> pts;
  for (std::size_t i = 0; i <= n; ++i) {  // O(chords)
    const double f = static_cast<double>(i) / static_cast<double>(n);
    const double th = a0 + dir * sweep * f, r = r0 + (r1 - r0) * f;
    pts.push_back({cx + r * std::cos(th), cy + r * std::sin(th), start[2] + (end[2] - start[2]) * f});
  }
  pts.back() = end;
  return pts;
}

// The parameter interval of segment ab whose XY lies within `window` of (cx, cy); false if none.
bool clip_to_window(const P3& a, const P3& b, double cx, double cy, double window, double& t0, double& t1) {
  t0 = 0, t1 = 1;
  if (window <= 0) return true;
  const double dx = b[0] - a[0], dy = b[1] - a[1], ox = a[0] - cx, oy = a[1] - cy;
  const double qa = dx * dx + dy * dy, qb = 2 * (ox * dx + oy * dy), qc = ox * ox + oy * oy - window * window;
  if (qa <= tol::xy_length_mm * tol::xy_length_mm) return qc <= 0;
  const double disc = qb * qb - 4 * qa * qc;
  if (disc < 0) return false;
  t0 = std::max(0.0, (-qb - std::sqrt(disc)) / (2 * qa));
  t1 = std::min(1.0, (-qb + std::sqrt(disc)) / (2 * qa));
  return t0 <= t1;
}

/// The maximum of f over [t0, t1] of a segment `len` long, f 1-Lipschitz in the distance travelled
/// (the branch and bound of exact_gouge.hpp): spans whose bound cannot beat max(best() +
/// resolution, floor) are dropped, the bound no higher than `ceiling` (the most f can be).
/// `eval(t)` returns f(t) and keeps the best itself. O(evaluations ≤ kMaxEvaluationsPerSegment).
template <class Eval, class Best>
void lipschitz_max(double len, double t0, double t1, double resolution, double floor, double ceiling, Eval&& eval,
                   Best&& best) {
  struct Span {
    double ta, tb, fa, fb;
  };
  std::vector<Span> stack{{t0, t1, eval(t0), t1 > t0 ? eval(t1) : -1e300}};
  std::size_t evaluations = 2;
  while (!stack.empty() && evaluations < kMaxEvaluationsPerSegment) {  // O(evaluations)
    const Span s = stack.back();
    stack.pop_back();
    const double bound = std::min(ceiling, 0.5 * (s.fa + s.fb + len * (s.tb - s.ta)));
    if (bound <= std::max(best() + resolution, floor)) continue;
    const double tm = 0.5 * (s.ta + s.tb);
    const double fm = eval(tm);
    ++evaluations;
    stack.push_back({s.ta, tm, s.fa, fm});
    stack.push_back({tm, s.tb, fm, s.fb});
  }
}

// The maximum of the core's penetration along ab over [t0, t1], within `res`. O(evaluations ·
// core_penetration).
void segment_max(const PartSolid& part, const Core& k, const P3& a, const P3& b, double t0, double t1,
                 const ExactGougeOptions& opt, Penetration& best, std::size_t item, std::size_t line) {
  lipschitz_max(
      norm(sub(b, a)), t0, t1, opt.resolution_mm, opt.tolerance_mm, HUGE_VAL,
      [&](double t) {
        const P3 p = lerp(a, b, t);
        const double d = core_penetration(part, k, p);
        if (d > best.depth_mm) best = {d, p, item, line};
        return d;
      },
      [&] { return best.depth_mm; });
}

}  // namespace

PartSolid::PartSolid(const ingest::Mesh& mesh, double z_shift) {
  if (mesh.F.rows() == 0) throw Error("simulate: the exact gouge check needs a mesh with triangles");
  const auto nv = mesh.V.rows();
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin, extent = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {  // O(F)
    std::array<P3, 3> t{};
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto v = mesh.F(f, k);
      if (v < 0 || v >= nv) throw Error("simulate: face " + std::to_string(f) + " indexes outside the vertices");
      t[static_cast<std::size_t>(k)] = {mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2) + z_shift};
    }
    const std::array<double, 4> b{std::min({t[0][0], t[1][0], t[2][0]}), std::min({t[0][1], t[1][1], t[2][1]}),
                                  std::max({t[0][0], t[1][0], t[2][0]}), std::max({t[0][1], t[1][1], t[2][1]})};
    xmin = std::min(xmin, b[0]), ymin = std::min(ymin, b[1]), xmax = std::max(xmax, b[2]), ymax = std::max(ymax, b[3]);
    extent += std::max(b[2] - b[0], b[3] - b[1]);
    tri_.push_back(t);
    box_.push_back(b);
  }
  x0_ = xmin, y0_ = ymin;
  bin_ = std::max(tol::exact_min_bin_mm, 2 * extent / static_cast<double>(tri_.size()));
  while (((xmax - xmin) / bin_ + 1) * ((ymax - ymin) / bin_ + 1) > tol::exact_max_bins) bin_ *= 2;
  nx_ = static_cast<std::size_t>((xmax - xmin) / bin_) + 1;
  ny_ = static_cast<std::size_t>((ymax - ymin) / bin_) + 1;
  auto range = [&](double lo, double hi, double o, std::size_t n, std::size_t& a, std::size_t& b) {
    a = static_cast<std::size_t>(std::clamp(std::floor((lo - o) / bin_), 0.0, static_cast<double>(n - 1)));
    b = static_cast<std::size_t>(std::clamp(std::floor((hi - o) / bin_), 0.0, static_cast<double>(n - 1)));
  };
  start_.assign(nx_ * ny_ + 1, 0);
  for (int fill = 0; fill < 2; ++fill) {  // counting, then filling: O(F · bins per triangle)
    std::vector<std::uint32_t> at(start_.begin(), start_.end() - 1);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      std::size_t ix0, ix1, iy0, iy1;
      range(box_[t][0], box_[t][2], x0_, nx_, ix0, ix1);
      range(box_[t][1], box_[t][3], y0_, ny_, iy0, iy1);
      if (fill == 0) first_bin_.push_back({static_cast<std::uint32_t>(ix0), static_cast<std::uint32_t>(iy0)});
      for (std::size_t iy = iy0; iy <= iy1; ++iy)
        for (std::size_t ix = ix0; ix <= ix1; ++ix) {
          if (fill == 0)
            ++start_[iy * nx_ + ix + 1];
          else
            ids_[at[iy * nx_ + ix]++] = static_cast<std::uint32_t>(t);
        }
    }
    if (fill == 0) {
      for (std::size_t b = 0; b + 1 < start_.size(); ++b) start_[b + 1] += start_[b];
      ids_.resize(start_.back());
    }
  }
}

PartSolid::Probe PartSolid::probe(const gcode::Point3& p, double reach) const {
  Probe out;
  out.distance = reach;
  const auto lo = [&](double v, double o, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(std::floor((v - o) / bin_), 0.0, static_cast<double>(n - 1)));
  };
  const std::size_t ix0 = lo(p[0] - reach, x0_, nx_), ix1 = lo(p[0] + reach, x0_, nx_);
  const std::size_t iy0 = lo(p[1] - reach, y0_, ny_), iy1 = lo(p[1] + reach, y0_, ny_);
  // Each triangle of the bins once: in the first of its bins that the query's range holds (it is
  // stored in every bin its box meets). The answers are a maximum and a minimum: the order the
  // triangles come in does not change them.
  auto each = [&](auto&& visit) {
    for (std::size_t iy = iy0; iy <= iy1; ++iy)
      for (std::size_t ix = ix0; ix <= ix1; ++ix)
        for (std::uint32_t k = start_[iy * nx_ + ix]; k < start_[iy * nx_ + ix + 1]; ++k) {
          const std::uint32_t t = ids_[k];
          if (std::max<std::size_t>(ix0, first_bin_[t][0]) == ix && std::max<std::size_t>(iy0, first_bin_[t][1]) == iy)
            visit(t);
        }
  };
  double top = -std::numeric_limits<double>::infinity();
  each([&](std::uint32_t t) {  // O(candidates): the inside test first
    const auto& b = box_[t];
    if (p[0] < b[0] - reach || p[0] > b[2] + reach || p[1] < b[1] - reach || p[1] > b[3] + reach) return;
    const double h = height_over(tri_[t], p[0], p[1]);
    if (!std::isnan(h) && p[2] < h) top = std::max(top, h);
  });
  if (std::isfinite(top)) return {true, 0.0, top - p[2]};
  // The squared XY distance from p to the segment ab: no part of the strip below ab is nearer.
  auto xy_gap2 = [&](const P3& a, const P3& b) {
    const double ex = b[0] - a[0], ey = b[1] - a[1], l2 = ex * ex + ey * ey;
    const double t = l2 > 0 ? std::clamp(((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / l2, 0.0, 1.0) : 0.0;
    const double dx = p[0] - a[0] - t * ex, dy = p[1] - a[1] - t * ey;
    return dx * dx + dy * dy;
  };
  each([&](std::uint32_t t) {  // O(candidates): the distance to each prism's boundary
    // A prism's boundary is no nearer than its box in XY, a strip no nearer than its edge: what
    // lies farther than the nearest so far cannot lower the minimum (the same answer as measuring
    // every candidate within reach).
    const auto& b = box_[t];
    double& near = out.distance;
    if (p[0] < b[0] - near || p[0] > b[2] + near || p[1] < b[1] - near || p[1] > b[3] + near) return;
    const auto& v = tri_[t];
    near = std::min(near, point_triangle_distance(p, v[0], v[1], v[2]));
    for (const auto& [a, c] : {std::pair{0, 1}, {1, 2}, {2, 0}})
      if (xy_gap2(v[a], v[c]) < near * near) near = std::min(near, strip_distance(p, v[a], v[c]));
  });
  return out;
}

double penetration_at(const PartSolid& part, const tooling::Cutter& cutter, const gcode::Point3& tip) {
  return core_penetration(part, core_of(cutter), tip);
}

std::vector<gcode::Point3> item_starts(const gcode::Program& program, const gcode::Point3& start) {
  std::vector<P3> starts(program.items.size(), P3{kNaN, kNaN, kNaN});
  P3 pos = start;
  for (std::size_t it = 0; it < program.items.size(); ++it) {  // O(items)
    starts[it] = pos;
    const auto* mv = std::get_if<gcode::Move>(&program.items[it]);
    if (!mv) continue;
    for (std::size_t k = 0; k < 3; ++k)
      if (mv->axes & (1u << k)) pos[k] = mv->to[k];
  }
  return starts;
}

Penetration sweep_penetration(const PartSolid& part, const gcode::Program& program,
                              const std::vector<gcode::Point3>& starts, const std::vector<std::size_t>& items,
                              const tooling::Cutter& cutter, double cx, double cy, double window,
                              const ExactGougeOptions& opt) {
  const Core k = core_of(cutter);
  Penetration best;
  for (const std::size_t it : items) {  // O(moves · evaluations)
    if (it >= program.items.size() || it >= starts.size()) continue;
    const auto* mv = std::get_if<gcode::Move>(&program.items[it]);
    if (!mv) continue;
    P3 end = starts[it];
    for (std::size_t a = 0; a < 3; ++a)
      if (mv->axes & (1u << a)) end[a] = mv->to[a];
    if (!known_point(end)) continue;
    const P3 start = known_point(starts[it]) ? starts[it] : end;  // unknown start: placed at the end (as the sweep)
    const std::size_t line = it < program.source_line.size() ? program.source_line[it] : 0;
    const std::vector<P3> pts =
        known_point(starts[it]) ? move_points(*mv, start, end, opt.chord_tol_mm) : std::vector<P3>{end, end};
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {  // O(chords)
      double t0 = 0, t1 = 1;
      if (clip_to_window(pts[i], pts[i + 1], cx, cy, window, t0, t1))
        segment_max(part, k, pts[i], pts[i + 1], t0, t1, opt, best, it, line);
    }
  }
  return best;
}

std::vector<double> nearest_approach(const std::vector<PassTool>& passes, const std::vector<P3>& points, double reach,
                                     const ExactGougeOptions& opt) {
  if (!(std::isfinite(reach) && reach > 0)) throw Error("simulate: the nearest approach's reach must be > 0");
  std::vector<double> out(points.size(), reach);
  if (points.empty()) return out;
  // 1. Bins (edge: the widest cutter's R + reach) over the points.
  double widest = 0;
  for (const PassTool& pt : passes)  // O(passes)
    if (pt.program != nullptr && pt.cutter.shape() != tooling::CutterType::Drill)
      widest = std::max(widest, pt.cutter.radius());
  const double bin = widest + reach, margin = bin;
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (const P3& p : points)
    x0 = std::min(x0, p[0]), y0 = std::min(y0, p[1]), x1 = std::max(x1, p[0]), y1 = std::max(y1, p[1]);
  const auto nx = static_cast<std::size_t>((x1 - x0) / bin) + 1, ny = static_cast<std::size_t>((y1 - y0) / bin) + 1;
  if (!(static_cast<double>(nx) * static_cast<double>(ny) <= 5e7))
    throw Error("simulate: the nearest approach's points span " + std::to_string(nx * ny) + " bins (limit 50,000,000)");
  std::vector<std::int32_t> slot(nx * ny, -1);
  std::vector<std::vector<std::uint32_t>> lists;
  for (const P3& p : points) {  // O(points)
    auto& s = slot[static_cast<std::size_t>((p[1] - y0) / bin) * nx + static_cast<std::size_t>((p[0] - x0) / bin)];
    if (s < 0) s = static_cast<std::int32_t>(lists.size()), lists.emplace_back();
  }
  // 2. The moves as segments, each with its cutter, kept where listed in an
  //    occupied bin its XY corridor (the widest reach either side) meets.
  struct Seg {
    P3 a, b;
    const tooling::Cutter* cutter;
  };
  std::vector<Seg> segs;
  auto list = [&](const Seg& s) {  // O(bins of its box)
    const double lo_x = std::min(s.a[0], s.b[0]) - margin, hi_x = std::max(s.a[0], s.b[0]) + margin;
    const double lo_y = std::min(s.a[1], s.b[1]) - margin, hi_y = std::max(s.a[1], s.b[1]) + margin;
    if (hi_x < x0 || hi_y < y0 || lo_x > x0 + bin * static_cast<double>(nx) ||
        lo_y > y0 + bin * static_cast<double>(ny))
      return;
    const auto bx0 = static_cast<std::size_t>(std::max(0.0, (lo_x - x0) / bin)),
               by0 = static_cast<std::size_t>(std::max(0.0, (lo_y - y0) / bin));
    const std::size_t bx1 = std::min(nx - 1, static_cast<std::size_t>(std::max(0.0, (hi_x - x0) / bin))),
                      by1 = std::min(ny - 1, static_cast<std::size_t>(std::max(0.0, (hi_y - y0) / bin)));
    bool listed = false;
    for (std::size_t by = by0; by <= by1; ++by)
      for (std::size_t bx = bx0; bx <= bx1; ++bx) {
        const std::int32_t s_id = slot[by * nx + bx];
        if (s_id < 0) continue;
        const P3 c{x0 + (static_cast<double>(bx) + 0.5) * bin, y0 + (static_cast<double>(by) + 0.5) * bin, 0};
        const P3 a{s.a[0], s.a[1], 0}, b{s.b[0], s.b[1], 0};
        if (point_segment_distance(c, a, b) > margin + bin * std::numbers::sqrt2 / 2) continue;
        lists[static_cast<std::size_t>(s_id)].push_back(static_cast<std::uint32_t>(segs.size()));
        listed = true;
      }
    if (listed) segs.push_back(s);
  };
  for (const PassTool& pt : passes) {  // O(moves · chords)
    if (pt.program == nullptr || pt.cutter.shape() == tooling::CutterType::Drill) continue;
    const std::vector<P3> starts = item_starts(*pt.program, {kNaN, kNaN, kNaN});
    for (std::size_t it = 0; it < pt.program->items.size(); ++it) {
      const auto* mv = std::get_if<gcode::Move>(&pt.program->items[it]);
      if (!mv) continue;
      P3 end = starts[it];
      for (std::size_t k = 0; k < 3; ++k)
        if (mv->axes & (1u << k)) end[k] = mv->to[k];
      if (!known_point(end)) continue;
      const std::vector<P3> pts =
          known_point(starts[it]) ? move_points(*mv, starts[it], end, opt.chord_tol_mm) : std::vector<P3>{end, end};
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) list({pts[i], pts[i + 1], &pt.cutter});
    }
  }
  // 3. Each point: the least distance along each listed segment within its window.
  const auto n = static_cast<std::ptrdiff_t>(points.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const P3& p = points[static_cast<std::size_t>(q)];
    double best = reach;
    const auto& list = lists[static_cast<std::size_t>(
        slot[static_cast<std::size_t>((p[1] - y0) / bin) * nx + static_cast<std::size_t>((p[0] - x0) / bin)])];
    for (const std::uint32_t k : list) {  // O(listed segments · evaluations)
      const Seg& s = segs[k];
      double t0 = 0, t1 = 1;
      if (!clip_to_window(s.a, s.b, p[0], p[1], s.cutter->radius() + reach, t0, t1)) continue;
      // (the distance's maximum of its negative: never above 0)
      lipschitz_max(
          norm(sub(s.b, s.a)), t0, t1, opt.resolution_mm, -HUGE_VAL, 0.0,
          [&](double t) {
            const P3 tip = lerp(s.a, s.b, t);
            const double d = s.cutter->distance_to_solid(tip[0], tip[1], tip[2], p[0], p[1], p[2]);
            best = std::min(best, d);
            return -d;
          },
          [&] { return -best; });
    }
    out[static_cast<std::size_t>(q)] = best;
  }
  return out;
}

void confirm_gouges(SurfaceMetrics& m, const ZMap& machined, const std::vector<double>& design, const PartSolid& part,
                    const std::vector<PassTool>& passes, const ExactGougeOptions& opt) {
  const GridSpec& g = machined.spec();
  const auto& z = machined.heights();
  const auto& stamps = machined.stamps();
  // 1. The z-map's gouge per pass, and its gouge places: per move (stamp), its deepest gouge
  //    cell. O(cells).
  //    Per chunk of cells (fixed, whatever the thread count), merged in chunk order with the
  //    comparisons of one pass in cell order (the first cell keeps a tie): the same figures.
  using ByMove = std::map<std::uint32_t, std::pair<double, std::size_t>>;
  auto keep = [](ByMove& by_move, std::uint32_t stamp, double en, std::size_t i) {
    auto [at, fresh] = by_move.try_emplace(stamp, en, i);
    if (!fresh && en < at->second.first) at->second = {en, i};
  };
  struct Chunk {
    std::vector<double> pass_max;
    ByMove by_move;
  };
  constexpr std::size_t kChunk = 1 << 16;
  const std::size_t nchunks = (g.cells() + kChunk - 1) / kChunk;
  std::vector<Chunk> chunks(nchunks, Chunk{std::vector<double>(machined.passes(), 0.0), {}});
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(nchunks); ++c) {  // O(cells)
    Chunk& ch = chunks[static_cast<std::size_t>(c)];
    const std::size_t i0 = static_cast<std::size_t>(c) * kChunk, i1 = std::min(g.cells(), i0 + kChunk);
    for (std::size_t i = i0; i < i1; ++i) {
      if (std::isnan(design[i]) || stamps[i] == 0 || !(z[i] < design[i])) continue;
      const double en = (z[i] - design[i]) * metrics::cos_slope(g, design, i);
      if (MoveRef ref; machined.origin(i, ref) && ref.pass < ch.pass_max.size())
        ch.pass_max[ref.pass] = std::max(ch.pass_max[ref.pass], -en);
      if (m.gouged && en < -opt.tolerance_mm) keep(ch.by_move, stamps[i], en, i);
    }
  }
  m.pass_max_gouge_mm.assign(machined.passes(), 0.0);
  ByMove by_move;
  for (const Chunk& ch : chunks) {  // O(chunks · passes + places)
    for (std::size_t k = 0; k < ch.pass_max.size(); ++k)
      m.pass_max_gouge_mm[k] = std::max(m.pass_max_gouge_mm[k], ch.pass_max[k]);
    for (const auto& [stamp, place] : ch.by_move) keep(by_move, stamp, place.first, place.second);
  }
  if (!m.gouged) return;
  std::vector<std::pair<double, std::size_t>> places;
  for (const auto& [stamp, place] : by_move) places.push_back(place);
  std::sort(places.begin(), places.end());  // deepest first; ties by cell
  m.gouge_checked = true;
  m.zmap_max_gouge_mm = m.max_gouge_mm;
  m.zmap_gouge_places = places.size();
  std::size_t checked = 0;
  std::vector<double> exact_of_pass(m.pass_max_gouge_mm.size(), kNaN);
  // 2. Each place's move and its neighbours swept exactly near the place.
  std::map<std::size_t, std::vector<P3>> starts;
  double deepest = 0;
  bool confirmed = false;
  MoveRef deepest_move, first_move;
  std::size_t deepest_cell = SIZE_MAX;
  P3 deepest_tip{};
  for (std::size_t p = 0; p < places.size() && checked < opt.max_places; ++p) {  // O(max_places · moves · evaluations)
    const std::size_t cell = places[p].second;
    MoveRef ref;
    if (!machined.origin(cell, ref)) continue;
    // A pass machined before this z-map was saved and read back has no program here: unchecked.
    if (ref.pass >= passes.size() || passes[ref.pass].program == nullptr) continue;
    ++checked;
    const PassTool& pt = passes[ref.pass];
    auto it = starts.find(ref.pass);
    if (it == starts.end()) it = starts.emplace(ref.pass, item_starts(*pt.program, {kNaN, kNaN, kNaN})).first;
    std::vector<std::size_t> items;
    for (std::size_t k = ref.item >= opt.neighbours ? ref.item - opt.neighbours : 0; k <= ref.item + opt.neighbours;
         ++k)
      items.push_back(k);
    const double cx = g.x(cell % g.nx), cy = g.y(cell / g.nx);
    const double window = pt.cutter.radius() + 2 * g.cell;
    const Penetration pen = sweep_penetration(part, *pt.program, it->second, items, pt.cutter, cx, cy, window, opt);
    // The pass's figure from its checked places (its deepest z-map place comes first).
    if (ref.pass < exact_of_pass.size()) {
      double& e = exact_of_pass[ref.pass];
      e = std::isnan(e) ? std::max(pen.depth_mm, 0.0) : std::max(e, pen.depth_mm);
    }
    if (!(pen.depth_mm > opt.tolerance_mm)) {  // clear within the tolerance: a z-map artefact
      ++m.gouge_places_refuted;
      deepest = std::max(deepest, pen.depth_mm);
      continue;
    }
    if (!confirmed || ref.pass < first_move.pass || (ref.pass == first_move.pass && pen.item < first_move.item))
      first_move = {ref.pass, pen.item, pen.line};
    if (!confirmed || pen.depth_mm > deepest) {
      deepest = pen.depth_mm;
      deepest_move = {ref.pass, pen.item, pen.line};
      deepest_cell = cell;
      deepest_tip = pen.tip;
    }
    confirmed = true;
  }
  // 3. The confirmed figures replace the z-map's.
  for (std::size_t k = 0; k < exact_of_pass.size(); ++k)  // O(passes)
    if (!std::isnan(exact_of_pass[k])) m.pass_max_gouge_mm[k] = exact_of_pass[k];
  m.gouge_places_checked = checked;
  m.gouged = confirmed;
  m.max_gouge_mm = deepest;
  m.gouge_has_move = confirmed;
  m.gouge_cell = confirmed ? deepest_cell : SIZE_MAX;
  m.gouge_move = confirmed ? deepest_move : MoveRef{};
  m.first_gouge_move = confirmed ? first_move : MoveRef{};
  m.gouge_x_mm = confirmed ? deepest_tip[0] : 0;
  m.gouge_y_mm = confirmed ? deepest_tip[1] : 0;
}

}  // namespace millnet::simulate
