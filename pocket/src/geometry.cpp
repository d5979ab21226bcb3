// Pocket geometry: segments, arcs, distances, areas, winding-number inside tests, validation.
// All lengths in mm. A segment of a loop carries the DXF bulge = tan(sweep/4).
#include "millnet/pocket/geometry.hpp"

#include "geometry_internal.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

namespace millnet::pocket {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;

using detail::cross;

/// Angle of (q − p0) measured from the arc start, in [0, 2π), in the arc's own sense of travel.
double angle_from_start(const Arc& arc, double phi) {
  double d = arc.sweep > 0 ? phi - arc.start_angle : arc.start_angle - phi;
  d = std::fmod(d, kTwoPi);
  if (d < 0) d += kTwoPi;
  return d;
}

Vec2 closest_on_line(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 d = b - a;
  const double l2 = d.squaredNorm();
  if (l2 <= 0) return a;
  const double t = std::clamp((p - a).dot(d) / l2, 0.0, 1.0);
  return a + t * d;
}
}  // namespace

namespace detail {

bool angle_in_arc(const Arc& arc, double phi) {
  const double d = angle_from_start(arc, phi);
  // Accept a tiny angular slack so that arc end points count as on the arc.
  return d <= std::abs(arc.sweep) + 1e-12 || d >= kTwoPi - 1e-12;
}

bool point_on_arc_span(const Arc& arc, const Vec2& q) {
  return angle_in_arc(arc, std::atan2(q.y() - arc.center.y(), q.x() - arc.center.x()));
}

BoxTree::BoxTree(std::vector<BBox> boxes) : boxes_(std::move(boxes)), idx_(boxes_.size()) {
  for (std::size_t i = 0; i < idx_.size(); ++i) idx_[i] = i;
  nodes_.reserve(2 * idx_.size() / 4 + 1);
  if (!idx_.empty()) (void)build(0, idx_.size());
}

// O(n log n): a median split per level (nth_element), depth ≈ log2(n / 8).
std::size_t BoxTree::build(std::size_t begin, std::size_t end) {
  const std::size_t me = nodes_.size();
  nodes_.push_back({});
  BBox b;
  for (std::size_t k = begin; k < end; ++k) {
    b.lo = b.lo.cwiseMin(boxes_[idx_[k]].lo);
    b.hi = b.hi.cwiseMax(boxes_[idx_[k]].hi);
  }
  nodes_[me].box = b;
  nodes_[me].begin = begin;
  nodes_[me].end = end;
  if (end - begin <= 8) return me;
  const int axis = (b.hi.x() - b.lo.x()) >= (b.hi.y() - b.lo.y()) ? 0 : 1;
  const std::size_t mid = begin + (end - begin) / 2;
  const auto first = idx_.begin() + static_cast<std::ptrdiff_t>(begin);
  std::nth_element(first, idx_.begin() + static_cast<std::ptrdiff_t>(mid),
                   idx_.begin() + static_cast<std::ptrdiff_t>(end), [&](std::size_t u, std::size_t v) {
                     const double cu = boxes_[u].lo(axis) + boxes_[u].hi(axis),
                                  cv = boxes_[v].lo(axis) + boxes_[v].hi(axis);
                     return cu < cv || (cu == cv && u < v);
                   });
  const std::size_t l = build(begin, mid);
  const std::size_t r = build(mid, end);
  nodes_[me].left = l;
  nodes_[me].right = r;
  return me;
}

void BoxTree::overlapping(const BBox& q, std::vector<std::size_t>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  std::size_t stack[128];
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!n.box.overlaps(q)) continue;
    if (n.left == 0) {
      for (std::size_t k = n.begin; k < n.end; ++k)
        if (boxes_[idx_[k]].overlaps(q)) out.push_back(idx_[k]);
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
}

BBox bbox(const Segment& s) {
  BBox b;
  b.lo = s.a.cwiseMin(s.b);
  b.hi = s.a.cwiseMax(s.b);
  if (!s.is_arc()) return b;
  const Arc arc = arc_of(s);
  // Axis extreme points of the circle that lie on the arc widen the box.
  for (int k = 0; k < 4; ++k) {
    const double phi = k * kPi / 2;
    if (angle_in_arc(arc, phi)) {
      const Vec2 q = arc.center + arc.radius * Vec2(std::cos(phi), std::sin(phi));
      b.lo = b.lo.cwiseMin(q);
      b.hi = b.hi.cwiseMax(q);
    }
  }
  return b;
}

std::vector<Vec2> intersections(const Segment& s, const Segment& t) {
  std::vector<Vec2> out;
  if (!s.is_arc() && !t.is_arc()) {
    const Vec2 r = s.b - s.a, u = t.b - t.a;
    const double den = cross(r, u);
    const Vec2 w = t.a - s.a;
    const double scale = std::max(r.norm() * u.norm(), 1e-300);
    if (std::abs(den) <= 1e-14 * scale) {
      // Parallel: collinear overlap is reported by its end points.
      if (std::abs(cross(w, r)) > 1e-12 * std::max(r.norm() * w.norm(), 1e-300)) return out;
      const double l2 = r.squaredNorm();
      if (l2 <= 0) return out;
      double t0 = w.dot(r) / l2, t1 = (t.b - s.a).dot(r) / l2;
      if (t0 > t1) std::swap(t0, t1);
      const double lo = std::max(0.0, t0), hi = std::min(1.0, t1);
      if (lo > hi + 1e-12) return out;
      out.push_back(s.a + lo * r);
      if (hi - lo > 1e-12) out.push_back(s.a + hi * r);
      return out;
    }
    const double ta = cross(w, u) / den, tb = cross(w, r) / den;
    constexpr double e = 1e-12;
    if (ta >= -e && ta <= 1 + e && tb >= -e && tb <= 1 + e) out.push_back(s.a + std::clamp(ta, 0.0, 1.0) * r);
    return out;
  }
  if (s.is_arc() && !t.is_arc()) return intersections(t, s);
  if (!s.is_arc() && t.is_arc()) {
    // Line s against circle of t.
    const Arc arc = arc_of(t);
    const Vec2 d = s.b - s.a, f = s.a - arc.center;
    const double A = d.squaredNorm(), B = 2 * f.dot(d), C = f.squaredNorm() - arc.radius * arc.radius;
    if (A <= 0) return out;
    double disc = B * B - 4 * A * C;
    const double eps = 1e-12 * std::max(B * B, std::abs(4 * A * C));
    if (disc < -eps) return out;
    disc = std::max(disc, 0.0);
    const double sq = std::sqrt(disc);
    const double roots[2] = {(-B - sq) / (2 * A), (-B + sq) / (2 * A)};
    const int nroots = sq == 0.0 ? 1 : 2;
    for (int k = 0; k < nroots; ++k) {
      const double tt = roots[k];
      if (tt < -1e-12 || tt > 1 + 1e-12) continue;
      const Vec2 q = s.a + std::clamp(tt, 0.0, 1.0) * d;
      if (point_on_arc_span(arc, q)) out.push_back(q);
    }
    return out;
  }
  // Arc against arc: circle–circle intersection, then both spans.
  const Arc p = arc_of(s), q = arc_of(t);
  const Vec2 dc = q.center - p.center;
  const double d = dc.norm();
  if (d <= 1e-12 * std::max(p.radius, 1.0)) {
    if (std::abs(p.radius - q.radius) > 1e-12 * p.radius) return out;
    // Same circle: overlapping spans are reported by the end points lying on the other arc.
    for (const Vec2& e : {t.a, t.b})
      if (point_on_arc_span(p, e)) out.push_back(e);
    for (const Vec2& e : {s.a, s.b})
      if (point_on_arc_span(q, e)) out.push_back(e);
    return out;
  }
  if (d > p.radius + q.radius + 1e-12 * d || d < std::abs(p.radius - q.radius) - 1e-12 * d) return out;
  const double a = (p.radius * p.radius - q.radius * q.radius + d * d) / (2 * d);
  const double h2 = p.radius * p.radius - a * a;
  const double h = h2 > 0 ? std::sqrt(h2) : 0.0;
  const Vec2 m = p.center + a * dc / d;
  const Vec2 perp(-dc.y() / d, dc.x() / d);
  const Vec2 cand[2] = {m + h * perp, m - h * perp};
  for (int k = 0; k < (h > 0 ? 2 : 1); ++k)
    if (point_on_arc_span(p, cand[k]) && point_on_arc_span(q, cand[k])) out.push_back(cand[k]);
  return out;
}

double segment_distance(const Segment& s, const Segment& t) {
  if (!intersections(s, t).empty()) return 0.0;
  double best = std::min({distance(s, t.a), distance(s, t.b), distance(t, s.a), distance(t, s.b)});
  // Interior critical points: for a line against an arc, the foot of the centre on the line;
  // for two arcs, the points on the line of centres.
  if (s.is_arc() != t.is_arc()) {
    const Segment& line = s.is_arc() ? t : s;
    const Segment& arcseg = s.is_arc() ? s : t;
    const Arc arc = arc_of(arcseg);
    const Vec2 foot = closest_on_line(line.a, line.b, arc.center);
    const Vec2 dir = foot - arc.center;
    const double dn = dir.norm();
    if (dn > 0) {
      const Vec2 q = arc.center + arc.radius * dir / dn;
      if (point_on_arc_span(arc, q)) best = std::min(best, (q - foot).norm());
    }
  } else if (s.is_arc() && t.is_arc()) {
    const Arc p = arc_of(s), q = arc_of(t);
    const Vec2 dc = q.center - p.center;
    const double d = dc.norm();
    if (d > 0) {
      const Vec2 u = dc / d;
      for (double sp : {1.0, -1.0})
        for (double sq : {1.0, -1.0}) {
          const Vec2 x = p.center + sp * p.radius * u, y = q.center + sq * q.radius * u;
          if (point_on_arc_span(p, x) && point_on_arc_span(q, y)) best = std::min(best, (x - y).norm());
        }
    }
  }
  return best;
}

bool strictly_inside_loop(const Loop& loop, const Vec2& p) {
  // Even-odd parity, exact for arcs and free of trigonometry: the loop's interior is the polygon
  // of its chords, toggled inside every circular segment (the region between an arc and its chord).
  // Every decision is taken for p' = p + (δ, ε) with 0 < ε ≪ δ infinitesimal (simulation of
  // simplicity), all from the same cross products, so a point exactly on a chord or on a
  // horizontal line through a vertex (the centre of a circle made of two half arcs, say) is
  // classified consistently; for p off the loop, p' and p are on the same side. Points on the loop
  // itself are the callers' business (they test loop_distance first). O(segments), no allocation.
  const std::size_t n = loop.size();
  bool in = false;
  for (std::size_t k = 0; k < n; ++k) {
    const Vertex& va = loop[k];
    const Vertex& vb = loop[(k + 1) % n];
    const Vec2 a = va.p(), e = vb.p() - a;
    double side = cross(e, p - a);                          // > 0: p left of a→b
    if (side == 0.0) side = e.y() != 0.0 ? -e.y() : e.x();  // cross(e, (δ, ε))
    if ((va.y > p.y()) != (vb.y > p.y())) {                 // half-open in y = the ε shift
      const bool left = vb.y > va.y ? side > 0 : side < 0;
      if (left) in = !in;  // the ray to +x crosses the chord
    }
    if (va.bulge != 0.0) {
      const Segment s{a, vb.p(), va.bulge};
      const Arc arc = arc_of(s);
      const Vec2 d = p - arc.center;
      double in_circle = d.squaredNorm() - arc.radius * arc.radius;
      if (in_circle == 0.0) in_circle = d.x() != 0.0 ? d.x() : d.y();
      const double side_m = cross(e, point_at(s, 0.5) - a);
      if (in_circle < 0 && side * side_m > 0) in = !in;
    }
  }
  return in;
}

double loop_distance(const Loop& loop, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = loop.size();
  for (std::size_t k = 0; k < n; ++k)
    best = std::min(best, distance(Segment{loop[k].p(), loop[(k + 1) % n].p(), loop[k].bulge}, p));
  return best;
}

Loop reversed(const Loop& loop) {
  // Segment k (v[k] → v[k+1], bulge b) becomes v[k+1] → v[k] with bulge −b.
  const std::size_t n = loop.size();
  Loop out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = loop[n - 1 - i];
    out[i].bulge = -loop[(2 * n - 2 - i) % n].bulge;
  }
  return out;
}

}  // namespace detail

std::vector<Segment> segments(const Loop& loop) {
  std::vector<Segment> out;
  const std::size_t n = loop.size();
  out.reserve(n);
  for (std::size_t k = 0; k < n; ++k) out.push_back({loop[k].p(), loop[(k + 1) % n].p(), loop[k].bulge});
  return out;
}

Arc arc_of(const Segment& s) {
  MILLNET_ASSERT(s.is_arc(), "arc_of on a straight segment");
  const Vec2 chord = s.b - s.a;
  const double c = chord.norm();
  const double b = s.bulge;
  Arc arc;
  arc.sweep = 4 * std::atan(b);
  arc.radius = c * (1 + b * b) / (4 * std::abs(b));
  // The centre lies on the chord's left normal at signed distance c(1 − b²)/(4b) from the midpoint.
  const Vec2 left = c > 0 ? Vec2(-chord.y() / c, chord.x() / c) : Vec2(0, 0);
  arc.center = 0.5 * (s.a + s.b) + left * (c * (1 - b * b) / (4 * b));
  arc.start_angle = std::atan2(s.a.y() - arc.center.y(), s.a.x() - arc.center.x());
  return arc;
}

double length(const Segment& s) {
  if (!s.is_arc()) return (s.b - s.a).norm();
  const Arc arc = arc_of(s);
  return arc.radius * std::abs(arc.sweep);
}

Vec2 point_at(const Segment& s, double t) {
  if (!s.is_arc()) return s.a + t * (s.b - s.a);
  if (t <= 0) return s.a;
  if (t >= 1) return s.b;
  const Arc arc = arc_of(s);
  const double phi = arc.start_angle + t * arc.sweep;
  return arc.center + arc.radius * Vec2(std::cos(phi), std::sin(phi));
}

Vec2 closest_point(const Segment& s, const Vec2& p) {
  if (!s.is_arc()) return closest_on_line(s.a, s.b, p);
  const Arc arc = arc_of(s);
  const Vec2 d = p - arc.center;
  const double dn = d.norm();
  if (dn > 0) {
    const double phi = std::atan2(d.y(), d.x());
    if (detail::angle_in_arc(arc, phi)) return arc.center + arc.radius * d / dn;
  }
  return (p - s.a).squaredNorm() <= (p - s.b).squaredNorm() ? s.a : s.b;
}

double distance(const Segment& s, const Vec2& p) { return (closest_point(s, p) - p).norm(); }

double distance(const Segment& s, const Vec2& p, const Vec2& q) {
  return detail::segment_distance(s, Segment{p, q, 0.0});
}

double signed_area(const Loop& loop) {
  // Shoelace over the chords plus the signed circular-segment area (r²/2)(θ − sin θ) of each arc.
  double a = 0;
  for (const Segment& s : segments(loop)) {
    a += 0.5 * cross(s.a, s.b);
    if (s.is_arc()) {
      const Arc arc = arc_of(s);
      a += 0.5 * arc.radius * arc.radius * (arc.sweep - std::sin(arc.sweep));
    }
  }
  return a;
}

double perimeter(const Loop& loop) {
  double p = 0;
  for (const Segment& s : segments(loop)) p += length(s);
  return p;
}

bool inside(const Loop& loop, const Vec2& p) {
  if (loop.size() < 2) return false;
  if (detail::loop_distance(loop, p) <= tol::on_curve_mm) return true;
  return detail::strictly_inside_loop(loop, p);
}

bool inside(const Region& region, const Vec2& p) {
  if (!inside(region.boundary, p)) return false;
  for (const Loop& isl : region.islands)
    if (detail::loop_distance(isl, p) > tol::on_curve_mm && detail::strictly_inside_loop(isl, p)) return false;
  return true;
}

std::vector<Vec2> flatten_open(const std::vector<Vertex>& pts, double chord_tol_mm) {
  std::vector<Vec2> out;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    out.push_back(pts[k].p());
    if (k + 1 == pts.size() || pts[k].bulge == 0.0) continue;
    const Segment s{pts[k].p(), pts[k + 1].p(), pts[k].bulge};
    const Arc arc = arc_of(s);
    // Chord of angle φ deviates r(1 − cos(φ/2)) from the arc.
    const double max_step = 2 * std::acos(1 - std::clamp(chord_tol_mm, 1e-9, arc.radius) / arc.radius);
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(arc.sweep) / std::max(max_step, 1e-6))));
    for (int i = 1; i < n; ++i) out.push_back(point_at(s, static_cast<double>(i) / n));
  }
  return out;
}

std::vector<Vec2> flatten(const Loop& loop, double chord_tol_mm) {
  if (loop.empty()) return {};
  Loop closed = loop;
  closed.push_back(loop.front());  // the closing segment, then the repeated first vertex dropped
  std::vector<Vec2> out = flatten_open(closed, chord_tol_mm);
  out.pop_back();
  return out;
}

double area(const Region& region) {
  double a = std::abs(signed_area(region.boundary));
  for (const Loop& isl : region.islands) a -= std::abs(signed_area(isl));
  return a;
}

namespace {

std::string where(const std::string& source, const std::string& loop_name) { return source + ": " + loop_name; }

std::string loop_name(std::size_t idx) {
  return idx == 0 ? std::string("boundary") : "island " + std::to_string(idx - 1);
}

std::string fmt_pt(const Vec2& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ")";
  return os.str();
}

/// Checks basic shape and splits |bulge| > 1; O(n) for a loop of n vertices.
void check_and_split(Loop& loop, const std::string& source, const std::string& name, NormalizeReport& rep) {
  if (loop.size() < 2)
    throw Error(where(source, name) + ": needs at least 2 vertices, got " + std::to_string(loop.size()));
  if (loop.size() == 2 && loop[0].bulge == 0.0 && loop[1].bulge == 0.0)
    throw Error(where(source, name) + ": two straight segments enclose no area");
  Loop out;
  std::size_t splits = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Vertex& v = loop[k];
    if (!std::isfinite(v.x) || !std::isfinite(v.y))
      throw Error(where(source, name) + ": vertex " + std::to_string(k) + " is not finite");
    if (!std::isfinite(v.bulge))
      throw Error(where(source, name) + ": vertex " + std::to_string(k) + ": bulge is not finite");
    const Vertex& w = loop[(k + 1) % loop.size()];
    if ((w.p() - v.p()).norm() <= tol::join_mm)
      throw Error(where(source, name) + ": zero-length segment at vertex " + std::to_string(k) + " " + fmt_pt(v.p()));
    if (std::abs(v.bulge) > 1.0) {
      // Split at the arc's midpoint: each half sweeps θ/2, bulge tan(θ/8).
      const Segment s{v.p(), w.p(), v.bulge};
      const double half = std::tan(std::atan(v.bulge) / 2);
      const Vec2 m = point_at(s, 0.5);
      out.push_back({v.x, v.y, half});
      out.push_back({m.x(), m.y(), half});
      ++splits;
    } else {
      out.push_back(v);
    }
  }
  if (splits > 0)
    rep.notes.push_back(name + ": split " + std::to_string(splits) + " arc(s) sweeping more than 180 degrees");
  loop = std::move(out);
}

/// Boxes of the segments, grown by 10·join_mm so that every contact intersections() can report
/// (it accepts points up to a relative 1e-12 beyond the ends) lies in both boxes.
std::vector<detail::BBox> grown_boxes(const std::vector<Segment>& segs) {
  std::vector<detail::BBox> boxes(segs.size());
  for (std::size_t i = 0; i < segs.size(); ++i) {
    detail::BBox b = detail::bbox(segs[i]);
    const double g = 10 * tol::join_mm + 1e-9 * std::max({b.lo.cwiseAbs().maxCoeff(), b.hi.cwiseAbs().maxCoeff(), 1.0});
    b.lo.array() -= g;
    b.hi.array() += g;
    boxes[i] = b;
  }
  return boxes;
}

/// Self-intersection check: segment pairs whose boxes overlap (a box tree), tested in the order of
/// the all-pairs loop it replaced, so the first crossing reported is the same. O(n log n + pairs).
void check_simple(const Loop& loop, const std::string& source, const std::string& name) {
  const std::vector<Segment> segs = segments(loop);
  const std::size_t n = segs.size();
  const detail::BoxTree tree(grown_boxes(segs));
  std::vector<std::size_t> near;
  for (std::size_t i = 0; i < n; ++i) {
    tree.overlapping(tree.box(i), near);
    std::sort(near.begin(), near.end());
    for (const std::size_t j : near) {
      if (j <= i) continue;
      const bool next = j == i + 1, wrap = (i == 0 && j == n - 1);
      for (const Vec2& q : detail::intersections(segs[i], segs[j])) {
        // Neighbours share a vertex; touching there is not a crossing.
        if (next && (q - segs[i].b).norm() <= tol::join_mm * 10) continue;
        if (wrap && (q - segs[i].a).norm() <= tol::join_mm * 10) continue;
        throw Error(where(source, name) + ": self-intersection between segment " + std::to_string(i) + " and segment " +
                    std::to_string(j) + " at " + fmt_pt(q));
      }
    }
  }
}

}  // namespace

NormalizeReport validate_and_normalize(Region& region, const std::string& source) {
  NormalizeReport rep;
  if (region.boundary.empty()) throw Error(source + ": empty pocket: no boundary");
  check_and_split(region.boundary, source, "boundary", rep);
  for (std::size_t k = 0; k < region.islands.size(); ++k)
    check_and_split(region.islands[k], source, loop_name(k + 1), rep);

  check_simple(region.boundary, source, "boundary");
  for (std::size_t k = 0; k < region.islands.size(); ++k) check_simple(region.islands[k], source, loop_name(k + 1));

  // Loops against loops: any contact is a crossing (a wall touching another leaves no room for a
  // tool and makes the region ill-defined). Pairs of segments of different loops whose boxes
  // overlap (one box tree over all), tested in the order (loop a, loop b, i, j) of the all-pairs
  // loop it replaced. O(N log N + pairs) for N segments in all.
  std::vector<const Loop*> loops{&region.boundary};
  for (const Loop& l : region.islands) loops.push_back(&l);
  std::vector<Segment> all;
  std::vector<std::pair<std::size_t, std::size_t>> id;  // (loop, segment)
  for (std::size_t a = 0; a < loops.size(); ++a) {
    const std::vector<Segment> s = segments(*loops[a]);
    for (std::size_t i = 0; i < s.size(); ++i) id.emplace_back(a, i);
    all.insert(all.end(), s.begin(), s.end());
  }
  if (loops.size() > 1) {
    const detail::BoxTree tree(grown_boxes(all));
    std::vector<std::array<std::size_t, 4>> pairs;  // (a, b, i, j) with a < b
    std::vector<std::size_t> near;
    for (std::size_t u = 0; u < all.size(); ++u) {
      tree.overlapping(tree.box(u), near);
      for (const std::size_t v : near)
        if (id[u].first < id[v].first) pairs.push_back({id[u].first, id[v].first, id[u].second, id[v].second});
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::size_t> start(loops.size() + 1, 0);
    for (std::size_t a = 0; a < loops.size(); ++a) start[a + 1] = start[a] + loops[a]->size();
    for (const auto& [a, b, i, j] : pairs) {
      const auto hits = detail::intersections(all[start[a] + i], all[start[b] + j]);
      if (!hits.empty())
        throw Error(where(source, loop_name(b)) + " crosses " + loop_name(a) + " (segment " + std::to_string(j) +
                    " meets segment " + std::to_string(i) + " at " + fmt_pt(hits.front()) + ")");
    }
  }
  for (std::size_t k = 0; k < region.islands.size(); ++k) {
    const Vec2 p = region.islands[k][0].p();
    if (!detail::strictly_inside_loop(region.boundary, p))
      throw Error(where(source, loop_name(k + 1)) + " lies outside the boundary (vertex 0 at " + fmt_pt(p) + ")");
    for (std::size_t m = 0; m < region.islands.size(); ++m)
      if (m != k && detail::strictly_inside_loop(region.islands[m], p))
        throw Error(where(source, loop_name(k + 1)) + " lies inside " + loop_name(m + 1) +
                    " (islands inside islands are not supported)");
  }

  if (signed_area(region.boundary) < 0) {
    region.boundary = detail::reversed(region.boundary);
    rep.notes.push_back("boundary was clockwise: reversed to counter-clockwise");
  }
  for (std::size_t k = 0; k < region.islands.size(); ++k)
    if (signed_area(region.islands[k]) > 0) {
      region.islands[k] = detail::reversed(region.islands[k]);
      rep.notes.push_back(loop_name(k + 1) + " was counter-clockwise: reversed to clockwise");
    }
  return rep;
}

}  // namespace millnet::pocket
