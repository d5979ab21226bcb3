// T-partition (Tang et al.) and I-partition (Suh & Kim) of a reachable area, in the scan frame.
// See partition.hpp for the conventions.
#include "millnet/pocket/partition.hpp"

#include "millnet/core/error.hpp"

#include "clipper_bridge.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace millnet::pocket {

namespace {

using ClipperLib::cInt;
// Finer than the offset's 1e-4 mm grid so that slits of 2·tol::slit_half_mm stay several units
// wide while the area's vertices (already on the 1e-4 grid) are kept exactly.
constexpr double kPartitionScale = 1e5;
constexpr double kTiny = 1e-9;  // mm, strictness margin of ray contacts
constexpr double kPartitionInf = std::numeric_limits<double>::infinity();

/// Extrema of one loop by hysteresis (O(n)): a reversal of the y-direction counts only once y has
/// moved more than tol::srp_flat_mm away from the running extreme, so flat tops, Clipper rounding
/// and flattened arcs give one extremum each.
void loop_extrema(const std::vector<Vec2>& ring, int component, int loop, bool reflex_only, std::vector<Srp>& out) {
  const std::size_t n = ring.size();
  if (n < 3) return;
  const double tol = tol::srp_flat_mm;
  std::size_t i0 = 0;
  for (std::size_t k = 1; k < n; ++k)
    if (ring[k].y() < ring[i0].y()) i0 = k;
  auto at = [&](std::size_t k) -> const Vec2& { return ring[(i0 + k) % n]; };
  // Confirmed extremes as offsets from i0: (offset, is_max).
  std::vector<std::pair<std::size_t, bool>> ext;
  ext.emplace_back(0, false);  // the global minimum
  bool up = true;
  std::size_t cand = 0;
  for (std::size_t k = 1; k <= n; ++k) {  // k == n revisits i0 and closes the ring
    const double y = at(k).y();
    if (up) {
      if (y > at(cand).y())
        cand = k;
      else if (at(cand).y() - y > tol) {
        ext.emplace_back(cand, true);
        up = false;
        cand = k;
      }
    } else {
      if (y < at(cand).y())
        cand = k;
      else if (y - at(cand).y() > tol) {
        ext.emplace_back(cand, false);
        up = true;
        cand = k;
      }
    }
  }
  // Classify each extreme by the orientation of (before, span…, after): negative ⇒ reflex.
  for (const auto& [off, is_max] : ext) {
    const double yc = at(off).y();
    auto near = [&](std::size_t k) { return std::abs(at(k).y() - yc) <= tol; };
    std::size_t lo = off + n, hi = off + n;  // work with offsets shifted by n to step back freely
    std::size_t steps = 0;
    while (near(lo - 1) && steps < n) {
      --lo;
      ++steps;
    }
    while (near(hi + 1) && steps < n) {
      ++hi;
      ++steps;
    }
    if (steps >= n - 1) return;  // degenerate flat ring
    std::vector<Vec2> poly;
    poly.push_back(at(lo - 1));
    double xmin = kPartitionInf, xmax = -kPartitionInf;
    for (std::size_t k = lo; k <= hi; ++k) {
      poly.push_back(at(k));
      xmin = std::min(xmin, at(k).x());
      xmax = std::max(xmax, at(k).x());
    }
    poly.push_back(at(hi + 1));
    const bool reflex = shoelace_area(poly) < 0;
    if (reflex_only && !reflex) continue;  // convex extreme: not an SRP
    Srp s;
    s.p = at(off);
    s.span_x_min = xmin;
    s.span_x_max = xmax;
    s.kind = is_max ? SrpKind::R : SrpKind::L;
    s.component = component;
    s.loop = loop;
    s.reflex = reflex;
    out.push_back(s);
  }
}

struct Seg {
  Vec2 a, b;
};

/// All edges of component c plus the cut segments already placed. O(V).
std::vector<Seg> obstacles(const PolyArea& a, const std::vector<Cut>& cuts) {
  std::vector<Seg> segs;
  auto add_ring = [&](const std::vector<Vec2>& r) {
    for (std::size_t k = 0; k < r.size(); ++k) segs.push_back({r[k], r[(k + 1) % r.size()]});
  };
  add_ring(a.outer);
  for (const auto& h : a.holes) add_ring(h);
  for (const Cut& c : cuts)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) segs.push_back({c.pts[k], c.pts[k + 1]});
  return segs;
}

/// Largest x < x0 − kTiny where the ray from (x0, y) toward −x touches a segment (closed contact).
/// −inf when nothing is hit. O(segments).
double first_contact_left(const std::vector<Seg>& segs, double x0, double y) {
  double best = -kPartitionInf;
  for (const Seg& s : segs) {
    const double y0 = std::min(s.a.y(), s.b.y()), y1 = std::max(s.a.y(), s.b.y());
    if (y < y0 || y > y1) continue;
    double x;
    if (s.a.y() == s.b.y())
      x = std::max(s.a.x(), s.b.x());
    else
      x = s.a.x() + (y - s.a.y()) * (s.b.x() - s.a.x()) / (s.b.y() - s.a.y());
    if (s.a.y() == s.b.y() && std::min(s.a.x(), s.b.x()) < x0 - kTiny) x = std::min(x, x0 - 2 * kTiny);
    if (x < x0 - kTiny) best = std::max(best, x);
  }
  return best;
}

/// Smallest y > y0 + kTiny where the ray from (x, y0) toward +y touches a segment. O(segments).
double first_contact_up(const std::vector<Seg>& segs, double x, double y0) {
  double best = kPartitionInf;
  for (const Seg& s : segs) {
    const double x0 = std::min(s.a.x(), s.b.x()), x1 = std::max(s.a.x(), s.b.x());
    if (x < x0 || x > x1) continue;
    double y;
    if (s.a.x() == s.b.x()) {
      y = std::min(s.a.y(), s.b.y());
      if (y <= y0 + kTiny && std::max(s.a.y(), s.b.y()) > y0 + kTiny) y = y0 + 2 * kTiny;
    } else {
      y = s.a.y() + (x - s.a.x()) * (s.b.y() - s.a.y()) / (s.b.x() - s.a.x());
    }
    if (y > y0 + kTiny) best = std::min(best, y);
  }
  return best;
}

ClipperLib::Path partition_to_path(const std::vector<Vec2>& pts, bool want_ccw) {
  ClipperLib::Path p = clipper_bridge::to_path(pts, kPartitionScale);
  if (ClipperLib::Orientation(p) != want_ccw) ClipperLib::ReversePath(p);
  return p;
}

void collect_partition(const ClipperLib::PolyNode& node, std::vector<PolyArea>& out) {
  clipper_bridge::collect(node, out, kPartitionScale);
}

/// A rectangle of half-width tol::slit_half_mm around segment a→b, extended by `ext_a`/`ext_b`
/// beyond its ends.
ClipperLib::Path slit(const Vec2& a, const Vec2& b, double ext_a, double ext_b) {
  Vec2 d = b - a;
  const double len = d.norm();
  d = len > 0 ? Vec2(d / len) : Vec2(1, 0);
  const Vec2 nrm(-d.y(), d.x());
  const double e = tol::slit_half_mm;
  const Vec2 a2 = a - ext_a * d, b2 = b + ext_b * d;
  return partition_to_path({a2 - e * nrm, b2 - e * nrm, b2 + e * nrm, a2 + e * nrm}, true);
}

/// Faces = areas minus the slits of every cut. One Clipper difference, O(V log V).
std::vector<PolyArea> build_faces(const std::vector<PolyArea>& areas, const std::vector<std::vector<Cut>>& cuts) {
  ClipperLib::Clipper c;
  for (const PolyArea& a : areas) {
    c.AddPath(partition_to_path(a.outer, true), ClipperLib::ptSubject, true);
    for (const auto& h : a.holes) c.AddPath(partition_to_path(h, false), ClipperLib::ptSubject, true);
  }
  const double ext = 3 * tol::slit_half_mm;  // reach a little into the wall / hole that is hit
  for (const auto& comp_cuts : cuts)
    for (const Cut& cut : comp_cuts)
      for (std::size_t k = 0; k + 1 < cut.pts.size(); ++k)
        c.AddPath(slit(cut.pts[k], cut.pts[k + 1], ext, ext), ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  c.Execute(ClipperLib::ctDifference, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<PolyArea> out;
  collect_partition(tree, out);
  // Deterministic order: by lowest point, then x (Clipper's own order is deterministic too, but this
  // one is readable). O(F log F).
  std::vector<std::pair<Vec2, std::size_t>> key;
  for (std::size_t k = 0; k < out.size(); ++k) {
    Vec2 lo(kPartitionInf, kPartitionInf);
    for (const Vec2& v : out[k].outer)
      if (v.y() < lo.y() || (v.y() == lo.y() && v.x() < lo.x())) lo = v;
    key.emplace_back(lo, k);
  }
  std::sort(key.begin(), key.end(), [](const auto& u, const auto& v) {
    if (u.first.y() != v.first.y()) return u.first.y() < v.first.y();
    return u.first.x() < v.first.x();
  });
  std::vector<PolyArea> sorted;
  sorted.reserve(out.size());
  for (const auto& kv : key) sorted.push_back(std::move(out[kv.second]));
  return sorted;
}

/// The T-cut of SRP s: from the first contact to the left, along the scan line, to the SRP vertex.
bool t_cut(const std::vector<Seg>& segs, const Srp& s, Cut& cut) {
  const double x = first_contact_left(segs, s.span_x_min, s.p.y());
  if (!std::isfinite(x)) return false;
  cut.pts = {Vec2(x, s.p.y()), s.p};
  cut.nls = false;
  return true;
}

/// The I-cut joining R-SRP p to L-SRP q above it (q.y > p.y): one NLS (along y) and one scan-line
/// part, both free of walls and of the cuts in `segs`. False when the path is blocked.
bool i_cut(const std::vector<Seg>& segs, const Srp& p, const Srp& q, Cut& cut) {
  const double yp = p.p.y(), yq = q.p.y();
  if (yq <= yp + tol::srp_flat_mm) return false;
  cut.nls = true;
  if (p.p.x() <= q.p.x()) {
    // NLS up from p to height yq, then along the scan line to q.
    const double xn = p.p.x();
    const double hit = first_contact_up(segs, xn, yp);
    const bool under_q = xn >= q.span_x_min - kTiny && xn <= q.span_x_max + kTiny;
    if (under_q) {
      if (hit < yq - kTiny) return false;
    } else {
      if (hit <= yq + kTiny) return false;
      if (first_contact_left(segs, q.span_x_min, yq) >= xn - kTiny) return false;
    }
    cut.pts = {p.p, Vec2(xn, yq), q.p};
  } else {
    // Scan-line part left from p to x = q.x, then the NLS up to q.
    const double xn = q.p.x();
    if (xn < p.span_x_min - kTiny && first_contact_left(segs, p.span_x_min, yp) >= xn - kTiny) return false;
    const double hit = first_contact_up(segs, xn, yp);
    if (hit < yq - kTiny) return false;
    cut.pts = {p.p, Vec2(xn, yp), q.p};
  }
  return true;
}

struct Built {
  std::vector<std::vector<Cut>> cuts;  // per component
  std::vector<PolyArea> faces;
};

/// Cuts for every SRP: the given I-cuts first, then a T-cut for each SRP not in a pair.
Built build(const std::vector<PolyArea>& areas, const std::vector<Srp>& srps,
            const std::vector<std::vector<Cut>>& icuts, const std::vector<char>& paired) {
  Built b;
  b.cuts = icuts;
  for (std::size_t c = 0; c < areas.size(); ++c) {
    const auto segs = obstacles(areas[c], icuts[c]);
    for (std::size_t k = 0; k < srps.size(); ++k) {  // O(n_s · V)
      if (paired[k] || srps[k].component != static_cast<int>(c)) continue;
      Cut cut;
      if (t_cut(segs, srps[k], cut)) b.cuts[c].push_back(cut);
    }
  }
  b.faces = build_faces(areas, b.cuts);
  return b;
}

bool all_monotone(const std::vector<PolyArea>& faces) {
  return std::all_of(faces.begin(), faces.end(), [](const PolyArea& f) { return is_y_monotone(f); });
}

/// Islands grouped by overlapping y-projections (seed §4.1), per component. O(H log H).
std::vector<std::vector<int>> island_groups(const std::vector<PolyArea>& areas) {
  std::vector<std::vector<int>> group(areas.size());
  for (std::size_t c = 0; c < areas.size(); ++c) {
    const auto& holes = areas[c].holes;
    std::vector<std::pair<double, double>> span(holes.size());
    for (std::size_t h = 0; h < holes.size(); ++h) {
      double lo = kPartitionInf, hi = -kPartitionInf;
      for (const Vec2& v : holes[h]) {
        lo = std::min(lo, v.y());
        hi = std::max(hi, v.y());
      }
      span[h] = {lo, hi};
    }
    std::vector<std::size_t> order(holes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t u, std::size_t v) { return span[u].first < span[v].first; });
    group[c].assign(holes.size(), -1);
    int g = -1;
    double reach = -kPartitionInf;
    for (std::size_t h : order) {
      if (span[h].first > reach) ++g;
      reach = std::max(reach, span[h].second);
      group[c][h] = g;
    }
  }
  return group;
}

}  // namespace

namespace {
std::vector<Srp> extrema(const std::vector<PolyArea>& areas, bool reflex_only) {
  std::vector<Srp> out;
  for (std::size_t c = 0; c < areas.size(); ++c) {
    loop_extrema(areas[c].outer, static_cast<int>(c), 0, reflex_only, out);
    for (std::size_t h = 0; h < areas[c].holes.size(); ++h)
      loop_extrema(areas[c].holes[h], static_cast<int>(c), static_cast<int>(h + 1), reflex_only, out);
  }
  return out;
}
}  // namespace

std::vector<Srp> find_srps(const std::vector<PolyArea>& areas) { return extrema(areas, true); }

std::vector<Srp> find_extrema(const std::vector<PolyArea>& areas) { return extrema(areas, false); }

bool is_y_monotone(const PolyArea& area) {
  // A simple polygon is y-monotone iff it has no hole and no reflex y-extremum (no SRP).
  if (!area.holes.empty()) return false;
  return find_srps({area}).empty();
}

std::vector<std::pair<double, double>> scan_intervals(const PolyArea& area, double y) {
  std::vector<double> xs;
  auto ring = [&](const std::vector<Vec2>& r) {
    for (std::size_t k = 0; k < r.size(); ++k) {  // O(n)
      const Vec2& a = r[k];
      const Vec2& b = r[(k + 1) % r.size()];
      if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
    }
  };
  ring(area.outer);
  for (const auto& h : area.holes) ring(h);
  std::sort(xs.begin(), xs.end());
  std::vector<std::pair<double, double>> out;
  for (std::size_t k = 0; k + 1 < xs.size(); k += 2) out.emplace_back(xs[k], xs[k + 1]);
  return out;
}

namespace {

/// The I-partition's pairs (seed §4.3): an R-SRP and an L-SRP of another island group joined by an
/// I-cut where that merges two faces into one monotone face, each pair validated by a real build.
/// Updates icuts, paired (1 = in a pair, 2 = tried, no partner), best and part.nls.
void pair_srps(const std::vector<PolyArea>& areas, Partition& part, std::vector<std::vector<Cut>>& icuts,
               std::vector<char>& paired, Built& best) {
  const std::size_t ns = part.srps.size();
  const auto groups = island_groups(areas);
  auto group_of = [&](const Srp& s) {
    return s.loop == 0 ? -1 : groups[static_cast<std::size_t>(s.component)][static_cast<std::size_t>(s.loop - 1)];
  };
  // Seed §4.3: R-SRPs are taken from the low side of the pocket first ("left" in the seed's
  // frame), highest level first; level = position along the scan direction (+x is higher, the
  // side away from where T-cuts run).
  std::vector<std::size_t> rs, ls;
  for (std::size_t k = 0; k < ns; ++k) (part.srps[k].kind == SrpKind::R ? rs : ls).push_back(k);
  auto by_level = [&](std::size_t u, std::size_t v) {
    const Srp &a = part.srps[u], &b = part.srps[v];
    if (a.p.y() != b.p.y()) return a.p.y() < b.p.y();
    return a.p.x() > b.p.x();
  };
  std::sort(rs.begin(), rs.end(), by_level);
  std::sort(ls.begin(), ls.end(), by_level);  // nearest above first, then highest level
  int attempts = 0;
  constexpr int kMaxAttempts = 400;  // each attempt is one Clipper difference
  std::size_t next_start = ns;       // an R-SRP on the island just joined, if any
  while (attempts < kMaxAttempts) {
    std::size_t start = ns;
    if (next_start < ns && !paired[next_start])
      start = next_start;
    else
      for (std::size_t r : rs)
        if (!paired[r]) {
          start = r;
          break;
        }
    if (start == ns) break;
    const Srp& p = part.srps[start];
    bool joined = false;
    for (std::size_t l : ls) {  // O(n_L) candidates, each validated by a real build
      if (paired[l]) continue;
      const Srp& q = part.srps[l];
      if (q.component != p.component || q.p.y() <= p.p.y() + tol::srp_flat_mm) continue;
      if (p.loop != 0 && q.loop != 0 && group_of(p) == group_of(q)) continue;  // seed: same group never pairs
      const auto segs =
          obstacles(areas[static_cast<std::size_t>(p.component)], icuts[static_cast<std::size_t>(p.component)]);
      Cut cut;
      if (!i_cut(segs, p, q, cut)) continue;
      ++attempts;
      auto trial_cuts = icuts;
      trial_cuts[static_cast<std::size_t>(p.component)].push_back(cut);
      auto trial_paired = paired;
      trial_paired[start] = trial_paired[l] = 1;
      Built trial = build(areas, part.srps, trial_cuts, trial_paired);
      if (trial.faces.size() + 1 == best.faces.size() && all_monotone(trial.faces)) {
        icuts = std::move(trial_cuts);
        paired = std::move(trial_paired);
        best = std::move(trial);
        ++part.nls;
        joined = true;
        // Next start: the highest-level R-SRP on q's loop (seed §4.3).
        next_start = ns;
        for (std::size_t r : rs)
          if (!paired[r] && part.srps[r].component == q.component && part.srps[r].loop == q.loop &&
              (next_start == ns || part.srps[r].p.x() > part.srps[next_start].p.x()))
            next_start = r;
        break;
      }
      if (attempts >= kMaxAttempts) break;
    }
    if (!joined) {
      paired[start] = 2;  // no partner: keeps its T-cut (2 = tried; treated as "not in a pair")
      next_start = ns;
    }
  }
}

}  // namespace

Partition partition(const std::vector<PolyArea>& areas, PartitionKind kind) {
  Partition part;
  part.kind = kind;
  part.n_components = static_cast<int>(areas.size());
  for (const PolyArea& a : areas) part.n_islands += static_cast<int>(a.holes.size());
  part.srps = find_srps(areas);
  const std::size_t ns = part.srps.size();
  std::vector<char> paired(ns, 0);
  std::vector<std::vector<Cut>> icuts(areas.size());
  Built best = build(areas, part.srps, icuts, paired);  // the T-partition
  if (kind == PartitionKind::I) {
    pair_srps(areas, part, icuts, paired, best);
    for (auto& v : paired) v = (v == 1);
  }
  part.cuts.clear();
  for (auto& cc : best.cuts)
    for (auto& c : cc) part.cuts.push_back(std::move(c));
  part.faces = std::move(best.faces);
  return part;
}

Vec2 to_scan_frame(const Vec2& p, double angle_deg) {
  const double t = -angle_deg * std::numbers::pi / 180.0;
  const double c = std::cos(t), s = std::sin(t);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

Vec2 from_scan_frame(const Vec2& p, double angle_deg) {
  const double t = angle_deg * std::numbers::pi / 180.0;
  const double c = std::cos(t), s = std::sin(t);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

std::vector<PolyArea> to_scan_frame(const std::vector<PolyArea>& areas, double angle_deg) {
  std::vector<PolyArea> out = areas;
  for (PolyArea& a : out) {  // O(V)
    for (Vec2& v : a.outer) v = to_scan_frame(v, angle_deg);
    for (auto& h : a.holes)
      for (Vec2& v : h) v = to_scan_frame(v, angle_deg);
  }
  return out;
}

}  // namespace millnet::pocket
