// Pencil tracing (rest.hpp: pencil_passes, plan_pencil): the bitangent positions of a ball where
// neighbouring drops jump across a concave edge, chained into passes along the crease, with
// offset passes beside them (multi-pencil).
#include "millnet/finish/rest.hpp"

#include "boundary.hpp"
#include "rest_internal.hpp"
#include "sampling.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace millnet::finish {
namespace {

using detail::Grid;

/// The crossing of a concave edge between axis positions a and b (contacts far apart): bisection
/// keeping the half whose ends' contacts differ most, to 1e-5 mm; the lower side's CL point.
CLPoint bitangent(const DropCutter& tool, Eigen::Vector2d a, Eigen::Vector2d b, CLPoint ca, CLPoint cb) {
  while ((b - a).norm() > 1e-5) {  // ≤ 17 drops for a 1 mm edge
    const Eigen::Vector2d m = 0.5 * (a + b);
    const CLPoint cm = tool.drop(m.x(), m.y());
    if (cm.contact == Contact::None) break;
    if ((cm.cc - ca.cc).norm() < (cm.cc - cb.cc).norm())
      a = m, ca = cm;
    else
      b = m, cb = cm;
  }
  return ca.z <= cb.z ? ca : cb;
}

/// Two points further apart in Z than this × their XY distance (70°), and by more than
/// `link` / (2√2) (a grid cell), are not on one crease: jumps found at different heights of a steep
/// concave slope (test part s1), near in XY only. A crease that steep is the Z-levels' in rest finishing.
constexpr double kSteepestCrease = 2.7474774194546216;  // tan 70°

/// An open XY polyline moved by `d` along its left normal. The chained bitangent points jitter by a
/// fraction of the grid cell across the line, so the normal at a vertex is taken from the chord
/// between the points `span` behind and ahead of it along the line (the ends: one-sided), not from
/// its own short segments; vertices closer than span/8 to the last kept one are skipped. O(vertices).
std::vector<Eigen::Vector2d> offset_polyline(const std::vector<Eigen::Vector2d>& line, double d, double span) {
  std::vector<Eigen::Vector2d> pts;
  for (const Eigen::Vector2d& q : line)
    if (pts.empty() || (q - pts.back()).norm() >= span / 8) pts.push_back(q);
  if (pts.size() < 2) return {};
  std::vector<double> s(pts.size(), 0.0);  // arc length
  for (std::size_t i = 1; i < pts.size(); ++i) s[i] = s[i - 1] + (pts[i] - pts[i - 1]).norm();
  std::vector<Eigen::Vector2d> out;
  std::size_t back = 0, ahead = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (back + 1 < i && s[i] - s[back + 1] >= span) ++back;
    if (ahead < i) ahead = i;
    while (ahead + 1 < pts.size() && s[ahead] - s[i] < span) ++ahead;
    const Eigen::Vector2d t = pts[ahead] - pts[back];
    if (!(t.norm() > 0)) continue;
    out.push_back(pts[i] + d * Eigen::Vector2d(-t.y(), t.x()) / t.norm());
  }
  return out;
}

}  // namespace

std::vector<Pass> pencil_passes(const ingest::Mesh& mesh, const DropCutter& tool, double x0, double y0, double x1,
                                double y1, double cell_mm, double chord_tolerance_mm,
                                const std::vector<std::uint8_t>* mask, int offsets, double spacing) {
  if (!(std::isfinite(cell_mm) && cell_mm > 0)) throw Error("pencil: cell_mm must be > 0");
  if (offsets < 0 || offsets > 50) throw Error("pencil: offsets must be in 0…50 (got " + std::to_string(offsets) + ")");
  if (offsets > 0 && !(std::isfinite(spacing) && spacing > 0))
    throw Error("pencil: the offset passes' spacing must be > 0 (the stepover)");
  const Grid g{x0, y0, cell_mm, static_cast<int>(std::ceil((x1 - x0) / cell_mm - 1e-9)) + 1,
               static_cast<int>(std::ceil((y1 - y0) / cell_mm - 1e-9)) + 1};
  if (mask != nullptr && mask->size() != g.size()) throw Error("pencil: the mask is not the grid's");
  std::vector<Eigen::Vector2d> xy(g.size());
  for (int i = 0; i < g.ny; ++i)  // O(nodes)
    for (int j = 0; j < g.nx; ++j) xy[g.at(i, j)] = {g.x(j), g.y(i)};
  const std::vector<CLPoint> cl = tool.drop(xy);
  const double jump = std::max(6 * cell_mm, 0.5 * tool.cutter().radius());
  auto on = [&](std::size_t k) { return cl[k].contact != Contact::None && (mask == nullptr || (*mask)[k] != 0); };
  std::vector<std::vector<Eigen::Vector3d>> found(static_cast<std::size_t>(g.ny));
#pragma omp parallel for schedule(dynamic, 8)
  for (int i = 0; i < g.ny; ++i)  // each row's right and upper edges: O(nodes), rows apart
    for (int j = 0; j < g.nx; ++j) {
      const std::size_t k = g.at(i, j);
      if (!on(k)) continue;
      for (const auto& [di, dj] : {std::pair{0, 1}, {1, 0}}) {
        if (i + di >= g.ny || j + dj >= g.nx) continue;
        const std::size_t q = g.at(i + di, j + dj);
        if (!on(q) || (cl[k].cc - cl[q].cc).norm() <= jump) continue;
        const CLPoint c = bitangent(tool, xy[k], xy[q], cl[k], cl[q]);
        found[static_cast<std::size_t>(i)].emplace_back(c.x, c.y, c.z);
      }
    }
  std::vector<Eigen::Vector3d> pts;
  for (auto& row : found) pts.insert(pts.end(), row.begin(), row.end());
  // Between the chained points the path is sampled like any pass (detail::sample_segment: no chord
  // dips below the drop-cutter by more than tol::chord_below_mm) and simplified.
  const detail::Sampler s(mesh, tool);
  std::vector<std::vector<detail::Sample>> lines;
  const auto sampled = [&](const std::vector<Eigen::Vector2d>& line) {
    std::vector<detail::Sample> run;
    for (std::size_t k = 1; k < line.size(); ++k) {  // O(points · samples per chord) drops
      auto seg = detail::sample_chord(s, line[k - 1], line[k], chord_tolerance_mm);
      if (!run.empty()) seg.erase(seg.begin());
      run.insert(run.end(), seg.begin(), seg.end());
    }
    return run;
  };
  const double link = 2 * std::numbers::sqrt2 * cell_mm, rise_free = link / (2 * std::numbers::sqrt2);
  const auto on_one_crease = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    const double d = std::hypot(q.x() - p.x(), q.y() - p.y());
    return std::abs(q.z() - p.z()) <= std::max(rise_free, kSteepestCrease * d) ? d : HUGE_VAL;
  };
  for (const auto& line : detail::chain_points(pts, link, on_one_crease)) {
    if (line.size() < 2) continue;
    std::vector<Eigen::Vector2d> xy_line;
    for (const Eigen::Vector3d& q : line) xy_line.push_back(q.head<2>());
    for (const double side : {1.0, -1.0})  // multi-pencil: each side from the outermost in
      for (int k = offsets; k >= 1; --k)
        if (auto run = sampled(offset_polyline(xy_line, side * k * spacing, std::max(spacing, 4 * cell_mm)));
            run.size() >= 2)
          lines.push_back(std::move(run));
    for (auto& run : detail::rising_chords_split(line, s, chord_tolerance_mm, cell_mm))
      if (run.size() >= 2) lines.push_back(std::move(run));
  }
  return detail::to_passes(std::move(lines));
}

FinishPlan plan_pencil(const ingest::Mesh& mesh, const DropCutter& tool, FinishParams params, int offsets) {
  params.check();
  double x0 = params.x0, y0 = params.y0, x1 = params.x1, y1 = params.y1;
  if (!(x1 > x0 && y1 > y0))
    x0 = mesh.V.col(0).minCoeff(), y0 = mesh.V.col(1).minCoeff(), x1 = mesh.V.col(0).maxCoeff(),
    y1 = mesh.V.col(1).maxCoeff();
  const double cell = std::min(0.1, params.tool.radius() / 4);
  const double nodes = std::ceil((x1 - x0) / cell + 1) * std::ceil((y1 - y0) / cell + 1);
  if (!(nodes <= 5e7))
    throw Error("pencil: a grid of " + std::to_string(static_cast<long long>(nodes)) + " nodes at " +
                std::to_string(cell) + " mm exceeds the limit of 50,000,000");
  FinishPlan plan;
  plan.strategy = Strategy::SlopeMode;  // the program's header names pencil tracing below
  const detail::Fence fence(mesh, params.boundary);
  plan.passes = detail::clip_passes(
      fence,
      pencil_passes(mesh, tool, x0, y0, x1, y1, cell, params.chord_tolerance_mm, nullptr, offsets, params.stepover_mm),
      params.chord_tolerance_mm);
  if (plan.passes.empty())
    throw Error("pencil: no concave edge on the part for " + params.tool.describe() + " (nothing to trace)");
  params.comments.insert(params.comments.begin(),
                         offsets > 0
                             ? "pencil tracing: bitangent passes along concave edges, " + std::to_string(offsets) +
                                   " offset passes each side " + std::to_string(params.stepover_mm) + " mm apart"
                             : std::string("pencil tracing: bitangent passes along concave edges"));
  detail::relink(mesh, tool, params, plan);
  return plan;
}

namespace detail {

std::vector<std::vector<Eigen::Vector3d>> chain_points(const std::vector<Eigen::Vector3d>& pts, double link,
                                                       const Apart& apart) {
  if (pts.empty()) return {};
  double x0 = HUGE_VAL, y0 = HUGE_VAL;
  for (const auto& p : pts) x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y());
  auto key = [&](double x, double y) {
    return std::pair{static_cast<long>(std::floor((x - x0) / link)), static_cast<long>(std::floor((y - y0) / link))};
  };
  std::map<std::pair<long, long>, std::vector<std::size_t>> buckets;
  for (std::size_t k = 0; k < pts.size(); ++k) buckets[key(pts[k].x(), pts[k].y())].push_back(k);
  auto neighbours = [&](std::size_t k, auto&& visit) {
    const auto [bx, by] = key(pts[k].x(), pts[k].y());
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = buckets.find({bx + dx, by + dy});
        if (it == buckets.end()) continue;
        for (const std::size_t q : it->second)
          if (q != k && std::hypot(pts[q].x() - pts[k].x(), pts[q].y() - pts[k].y()) <= link)
            if (const double d = apart(pts[k], pts[q]); d <= link) visit(q, d);
      }
  };
  std::vector<int> degree(pts.size(), 0);
  for (std::size_t k = 0; k < pts.size(); ++k) neighbours(k, [&](std::size_t, double) { ++degree[k]; });
  std::vector<std::size_t> order(pts.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return degree[a] < degree[b]; });
  std::vector<std::uint8_t> used(pts.size(), 0);
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (const std::size_t s0 : order) {
    if (used[s0]) continue;
    std::vector<Eigen::Vector3d> line{pts[s0]};
    used[s0] = 1;
    for (std::size_t at = s0;;) {
      std::size_t best = pts.size();
      double best_d = HUGE_VAL;
      neighbours(at, [&](std::size_t q, double d) {
        if (!used[q] && (d < best_d || (d == best_d && q < best))) best = q, best_d = d;
      });
      if (best == pts.size()) break;
      used[best] = 1;
      line.push_back(pts[best]);
      at = best;
    }
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace detail
}  // namespace millnet::finish
