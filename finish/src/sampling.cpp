#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <numbers>

namespace millnet::finish::detail {
using tooling::Cutter;
using tooling::CutterType;
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// Slope (degrees from horizontal) of the surface normal at a contact. Facet: the triangle's
/// normal. Edge/vertex: the normal of the cutter surface at the contact (ball: towards the
/// centre; bull: towards the nearest point of the torus' centre circle); a flat end mill touching
/// with its rim meets a wall (90°).
double slope_at(const CLPoint& c, const ingest::Mesh& mesh, const Cutter& cutter) {
  if (c.contact == Contact::None || c.triangle < 0) return 0;
  if (c.contact == Contact::Facet) {
    const auto f = mesh.F.row(c.triangle);
    const Eigen::Vector3d a = mesh.V.row(f(0)).transpose();
    const Eigen::Vector3d b = mesh.V.row(f(1)).transpose();
    const Eigen::Vector3d d = mesh.V.row(f(2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(d - a);
    const double len = n.norm();
    if (!(len > 0)) return 90;
    return std::acos(std::min(1.0, std::abs(n.z()) / len)) * kRadToDeg;
  }
  const double rc = cutter.corner_radius;
  if (cutter.type == CutterType::Flat || !(rc > 0)) return 90;
  const Eigen::Vector2d axis(c.x, c.y);
  const Eigen::Vector2d to_cc(c.cc.x() - c.x, c.cc.y() - c.y);
  const double r_ring = cutter.radius() - rc;  // 0 for a ball
  Eigen::Vector3d centre(c.x, c.y, c.z + rc);
  const double d = to_cc.norm();
  if (r_ring > 0 && d > 0) centre.head<2>() += to_cc / d * r_ring;
  const Eigen::Vector3d n = centre - c.cc;
  const double len = n.norm();
  if (!(len > 0)) return 0;
  return std::acos(std::min(1.0, std::abs(n.z()) / len)) * kRadToDeg;
}

}  // namespace

Sampler::Sampler(const ingest::Mesh& mesh, const DropCutter& dropper) : mesh_(mesh), dropper_(dropper) {
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id.fetch_add(1, std::memory_order_relaxed);
  floor_z_ = mesh.V.col(2).minCoeff();
  top_z_ = mesh.V.col(2).maxCoeff();
}

std::size_t Sampler::drops() const {
  std::size_t n = 0;
  for (const Shard& s : drops_) n += s.n.load(std::memory_order_relaxed);
  return n;
}

CLPoint Sampler::drop(double x, double y) const {
  static std::atomic<std::size_t> threads_seen{0};
  thread_local const std::size_t shard = threads_seen.fetch_add(1, std::memory_order_relaxed) % kShards;
  drops_[shard].n.fetch_add(1, std::memory_order_relaxed);
  // A memo of this thread's last answers, by the point's bits: the strategies ask for the same
  // point again (the corner two chained segments share, a quarter point that becomes the next
  // midpoint: 9 % of the points s4's label asks for). The answer is a function of the point
  // alone, so a repeat is answered from the memo bit for bit.
  struct Memo {
    std::uint64_t owner = 0;
    CLPoint c;
  };
  constexpr int kMemoBits = 10;
  thread_local std::array<Memo, std::size_t{1} << kMemoBits> memo{};
  const auto bx = std::bit_cast<std::uint64_t>(x), by = std::bit_cast<std::uint64_t>(y);
  Memo& m = memo[((bx * 0x9E3779B97F4A7C15ULL) ^ (by * 0xC2B2AE3D27D4EB4FULL)) >> (64 - kMemoBits)];
  if (m.owner == id_ && std::bit_cast<std::uint64_t>(m.c.x) == bx && std::bit_cast<std::uint64_t>(m.c.y) == by)
    return m.c;
  // The query starts from this thread's previous contact (usually the answer or next to it): a
  // heuristic only — the drop-cutter's answer does not depend on the hint.
  thread_local std::int32_t hint = -1;
  const CLPoint c = dropper_.drop(x, y, hint);
  hint = c.triangle;
  m.owner = id_;
  m.c = c;
  return c;
}

double Sampler::z(double x, double y) const {
  const CLPoint c = drop(x, y);
  return c.contact == Contact::None || !(c.z > floor_z_) ? floor_z_ : c.z;
}

Sample Sampler::sample(double x, double y) const {
  const CLPoint c = drop(x, y);
  Sample s;
  if (c.contact == Contact::None || !(c.z > floor_z_)) {
    s.p = Eigen::Vector3d(x, y, floor_z_);
    return s;
  }
  s.p = Eigen::Vector3d(x, y, c.z);
  s.slope_deg = slope_at(c, mesh_, dropper_.cutter());
  return s;
}

std::vector<double> cl_heights(const Sampler& s, double x0, double y0, double x1, double y1, double step, int nx,
                               int ny) {
  std::vector<double> cl(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
#pragma omp parallel for schedule(dynamic, 4)
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j)
      cl[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)] =
          s.z(std::min(x0 + step * j, x1), std::min(y0 + step * i, y1));
  return cl;
}

std::vector<Sample> sample_segment(const Sampler& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double h0,
                                   double tol) {
  const double len = (b - a).norm();
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(len / h0)));
  std::vector<Sample> base(n + 1);
  std::vector<double> t(n + 1);
  for (std::size_t i = 0; i <= n; ++i) {
    t[i] = static_cast<double>(i) / static_cast<double>(n);
    const Eigen::Vector2d q = a + t[i] * (b - a);
    base[i] = s.sample(q.x(), q.y());
  }
  // Depth-first halving of each interval; output in order.
  std::vector<Sample> out;
  out.reserve(base.size() * 2);
  out.push_back(base[0]);
  struct Item {
    Sample a, b;
    double ta, tb;
  };
  std::vector<Item> stack;
  for (std::size_t i = 0; i < n; ++i) {
    stack.push_back({base[i], base[i + 1], t[i], t[i + 1]});
    while (!stack.empty()) {
      Item it = stack.back();
      stack.pop_back();
      const double seg = (it.tb - it.ta) * len;
      if (seg > 2 * tol::min_sample_mm) {
        const double tm = 0.5 * (it.ta + it.tb);
        const Eigen::Vector2d q = a + tm * (b - a);
        Sample m = s.sample(q.x(), q.y());
        const double chord = 0.5 * (it.a.p.z() + it.b.p.z());
        const double dev = m.p.z() - chord;  // > 0: the chord would pass under the surface
        double above = dev;
        // Where the path climbs or turns (a wall's edge, a crease), the CL can lie under the chord
        // at the midpoint and above it off the middle (concave then convex): test the quarter
        // points too. Gentle, smooth intervals keep the one midpoint test.
        const double rise = std::abs(it.b.p.z() - it.a.p.z());
        if (rise > 0.1 * seg || std::abs(it.b.slope_deg - it.a.slope_deg) > 5) {
          for (const double f : {0.25, 0.75}) {
            const double tq = it.ta + f * (it.tb - it.ta);
            const Eigen::Vector2d qq = a + tq * (b - a);
            const double zq = s.z(qq.x(), qq.y());
            above = std::max(above, zq - (it.a.p.z() + f * (it.b.p.z() - it.a.p.z())));
          }
        }
        if (above > 0.5 * tol::chord_below_mm || -dev > tol) {  // half: the dip between samples can be larger
          stack.push_back({m, it.b, tm, it.tb});                // second half after the first
          stack.push_back({it.a, m, it.ta, tm});
          continue;
        }
      }
      out.push_back(it.b);
    }
  }
  return out;
}

namespace {

/// Deviation of q from the chord a→b: (above, below) as non-negative numbers.
std::pair<double, double> deviation(const Sample& a, const Sample& b, const Sample& q, bool straight_xy) {
  if (straight_xy) {
    const double lab = (b.p.head<2>() - a.p.head<2>()).norm();
    const double t = lab > 0 ? (q.p.head<2>() - a.p.head<2>()).norm() / lab : 0.0;
    const double dz = q.p.z() - (a.p.z() + t * (b.p.z() - a.p.z()));
    return {std::max(dz, 0.0), std::max(-dz, 0.0)};
  }
  const Eigen::Vector3d ab = b.p - a.p;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((q.p - a.p).dot(ab) / l2, 0.0, 1.0) : 0.0;
  const double d = (q.p - (a.p + t * ab)).norm();
  return {d, d};  // curved XY: both sides held to chord_below
}

}  // namespace

std::vector<Sample> simplify(const std::vector<Sample>& pts, double tol, bool straight_xy) {
  if (pts.size() <= 2) return pts;
  std::vector<char> keep(pts.size(), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, pts.size() - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    std::size_t worst = 0;
    double worst_excess = 0;
    for (std::size_t k = i + 1; k < j; ++k) {
      const auto [above, below] = deviation(pts[i], pts[j], pts[k], straight_xy);
      const double lim_below = straight_xy ? tol : 0.5 * tol::chord_below_mm;
      const double excess = std::max(above / (0.5 * tol::chord_below_mm), below / lim_below);
      if (excess > 1 && excess > worst_excess) {
        worst_excess = excess;
        worst = k;
      }
    }
    if (worst != 0) {
      keep[worst] = 1;
      stack.push_back({worst, j});
      stack.push_back({i, worst});
    }
  }
  std::vector<Sample> out;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (keep[k]) out.push_back(pts[k]);
  return out;
}

double polyline_length(const std::vector<Sample>& pts) {
  double len = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) len += (pts[i].p - pts[i - 1].p).norm();
  return len;
}

std::vector<Sample> sample_chord(const Sampler& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tol) {
  return sample_segment(s, a, b, std::clamp((b - a).norm(), 1e-3, 0.25), tol);
}

std::vector<std::vector<Sample>> rising_chords_split(const std::vector<Eigen::Vector3d>& line, const Sampler& s,
                                                     double chord_tolerance_mm, double rise) {
  std::vector<std::vector<Sample>> runs(1);
  for (std::size_t k = 1; k < line.size(); ++k) {  // O(points · samples per chord)
    const std::vector<Sample> seg = sample_chord(s, line[k - 1].head<2>(), line[k].head<2>(), chord_tolerance_mm);
    const double top = std::max(line[k - 1].z(), line[k].z()) + rise;
    if (std::any_of(seg.begin(), seg.end(), [&](const Sample& q) { return q.p.z() > top; })) {
      if (!runs.back().empty()) runs.emplace_back();
      continue;
    }
    auto& run = runs.back();
    run.insert(run.end(), seg.begin() + (run.empty() ? 0 : 1), seg.end());
  }
  return runs;
}

std::vector<Pass> to_passes(std::vector<std::vector<Sample>> lines) {
  std::vector<Pass> out;
  out.reserve(lines.size());
  for (auto& l : lines) {
    Pass p;
    p.closed = is_closed(l);
    p.points.reserve(l.size());
    for (const Sample& s : l) p.points.push_back(s.p);
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<std::vector<Sample>> order_by_level(std::vector<std::vector<std::vector<Sample>>> levels, double near_mm) {
  std::vector<std::vector<Sample>> out;
  std::size_t left = 0;
  for (const auto& l : levels) left += l.size();
  std::vector<std::vector<char>> used(levels.size());
  for (std::size_t k = 0; k < levels.size(); ++k) used[k].assign(levels[k].size(), 0);
  Eigen::Vector2d at(0, 0);
  bool have_at = false;
  std::size_t level = 0;
  // The point of a candidate nearest to `at` (closed loops may start anywhere; open passes only
  // at their start, which keeps the climb direction).
  auto nearest = [&](const std::vector<Sample>& c, std::size_t* index) {
    double best = std::numeric_limits<double>::infinity();
    const std::size_t n = is_closed(c) ? c.size() - 1 : 1;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = (c[i].p.head<2>() - at).squaredNorm();
      if (d < best) {
        best = d;
        *index = i;
      }
    }
    return std::sqrt(best);
  };
  while (left > 0) {
    std::size_t pick_level = levels.size(), pick = 0, start = 0;
    double best = std::numeric_limits<double>::infinity();
    if (have_at && level + 1 < levels.size()) {  // go deeper on the same island
      for (std::size_t i = 0; i < levels[level + 1].size(); ++i) {
        if (used[level + 1][i]) continue;
        std::size_t idx = 0;
        const double d = nearest(levels[level + 1][i], &idx);
        if (d <= near_mm && d < best) {
          best = d, pick_level = level + 1, pick = i, start = idx;
        }
      }
    }
    if (pick_level == levels.size()) {  // else the highest level left, nearest loop
      for (std::size_t k = 0; k < levels.size() && pick_level == levels.size(); ++k) {
        for (std::size_t i = 0; i < levels[k].size(); ++i) {
          if (used[k][i]) continue;
          std::size_t idx = 0;
          const double d = have_at ? nearest(levels[k][i], &idx) : 0.0;
          if (pick_level == levels.size() || d < best) {
            best = d, pick_level = k, pick = i, start = idx;
          }
        }
      }
    }
    used[pick_level][pick] = 1;
    --left;
    level = pick_level;
    std::vector<Sample> c = std::move(levels[pick_level][pick]);
    if (is_closed(c) && start != 0) {  // rotate the loop (last point = first point)
      c.pop_back();
      std::rotate(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(start), c.end());
      c.push_back(c.front());
    }
    at = c.back().p.head<2>();
    have_at = true;
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace millnet::finish::detail
