// Passes aimed at the rest the trimmed passes do not come near (detail::aim_at_rest): for each
// design point still carrying rest, the tool's placement nearest to it; the placements that reach
// their point (and a few more) kept in the points' order where it is still uncovered, chained, and
// sampled between like any pass.
#include "rest_internal.hpp"
#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

namespace millnet::finish::detail {
namespace {

/// A placement of the tool (its tip; the drop-cutter's height over its XY) and its distance to
/// the point it is aimed at (+∞: the drop met nothing).
struct Aim {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  double gap = HUGE_VAL;
};

Aim placement(const DropCutter& tool, const Eigen::Vector2d& xy, const Eigen::Vector3d& p) {
  const CLPoint c = tool.drop(xy.x(), xy.y());
  if (c.contact == Contact::None) return {};
  return {Eigen::Vector3d(xy.x(), xy.y(), c.z),
          tool.cutter().distance_to_solid(xy.x(), xy.y(), c.z, p.x(), p.y(), p.z())};
}

/// The placement nearest to the design point p (unit normal n) a pattern search finds: from the
/// axis that touches p on its normal (a ball's centre on the normal) and from the axis over p, the
/// better of the two, then the best of eight neighbours tol::rest_aim_step_radii · R away, the
/// step halved where none is better, down to a 32nd of it (at most 64 rounds); it stops as soon as
/// the gap is within `good`. O(rounds) drops.
Aim nearest_placement(const DropCutter& tool, const Eigen::Vector3d& p, const Eigen::Vector3d& n, double good) {
  const tooling::Cutter& c = tool.cutter();
  const double r = c.radius(), rc = c.profile_corner_radius(), h = std::hypot(n.x(), n.y());
  Eigen::Vector2d start = p.head<2>() + rc * n.head<2>();
  if (h > 1e-9) start += (r - rc) / h * n.head<2>();
  Aim best = placement(tool, start, p);
  if (const Aim above = placement(tool, p.head<2>(), p); above.gap < best.gap) best = above;
  static constexpr std::array<std::array<double, 2>, 8> kDirs{{{1, 0},
                                                               {-1, 0},
                                                               {0, 1},
                                                               {0, -1},
                                                               {0.7071067811865476, 0.7071067811865476},
                                                               {-0.7071067811865476, 0.7071067811865476},
                                                               {0.7071067811865476, -0.7071067811865476},
                                                               {-0.7071067811865476, -0.7071067811865476}}};
  const double first = tol::rest_aim_step_radii * r;
  double step = first;
  for (int round = 0; round < 64 && step >= first / 32 && best.gap > good; ++round) {
    Aim next = best;
    for (const auto& d : kDirs)  // O(8) drops
      if (const Aim a = placement(tool, best.tip.head<2>() + step * Eigen::Vector2d(d[0], d[1]), p); a.gap < next.gap)
        next = a;
    if (next.gap < best.gap)
      best = next;
    else
      step /= 2;
  }
  return best;
}

}  // namespace

std::vector<Pass> aim_at_rest(const ingest::Mesh& mesh, const DropCutter& tool, RestPoints& points,
                              double chord_tolerance_mm, const std::function<bool(const Eigen::Vector3d&)>& allowed,
                              double lowest_tip, std::size_t min_points) {
  std::vector<std::size_t> left = points.uncleared();
  // Out of reach below the lowest tip allowed (a point within the threshold of the solid lies at
  // most that below its tip): on s4, the deep walls below the Ø1's stick-out. The same passes.
  std::erase_if(left, [&](std::size_t i) { return points.points()[i].z() + points.threshold() < lowest_tip; });
  if (left.empty()) return {};
  const double threshold = points.threshold(), r = tool.cutter().radius();
  // 1. Each point's nearest placement, on its own (any thread count).
  std::vector<Aim> aim(left.size());
  const auto n_left = static_cast<std::ptrdiff_t>(left.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t k = 0; k < n_left; ++k) {  // O(points left · rounds) drops
    const std::size_t i = left[static_cast<std::size_t>(k)];
    aim[static_cast<std::size_t>(k)] =
        nearest_placement(tool, points.points()[i], points.normals()[i], tol::rest_aim_within * threshold);
  }
  // 2. In the points' order: a placement that reaches its point, where no placement kept before
  //    has, and that reaches `min_points` points not yet cleared, is kept and clears
  //    them.
  std::vector<Eigen::Vector3d> tips, across;       // across: the tangent along which a lone tip strokes
  for (std::size_t k = 0; k < left.size(); ++k) {  // O(points left · points near)
    if (!(aim[k].gap <= threshold) || points.is_cleared(left[k]) || !allowed(aim[k].tip) ||
        points.count_at(aim[k].tip) < min_points)
      continue;
    points.clear_at(aim[k].tip);
    tips.push_back(aim[k].tip);
    const Eigen::Vector3d& n = points.normals()[left[k]];
    across.emplace_back(-n.y(), n.x(), 0);
  }
  // 3. Chained within tol::rest_aim_link_radii · R (3D), sampled between like any pass (no chord
  //    below the drop-cutter by more than tol::chord_below_mm); a chord that rises more than
  //    tol::rest_aim_rise_radii · R over both its ends (over a ridge between two creases) splits
  //    the chain. A lone tip is a stroke of that rise's length from it, across its point's normal.
  const Sampler s(mesh, tool);
  const double link = tol::rest_aim_link_radii * r, rise = tol::rest_aim_rise_radii * r;
  const Apart apart = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm(); };
  std::vector<std::vector<Sample>> lines;
  std::map<std::array<double, 3>, std::size_t> index;  // a tip's place in `tips`
  for (std::size_t k = 0; k < tips.size(); ++k) index.emplace(std::array{tips[k].x(), tips[k].y(), tips[k].z()}, k);
  for (const auto& line : chain_points(tips, link, apart)) {  // O(tips · samples between)
    if (line.size() == 1) {
      const std::size_t k = index.at({line[0].x(), line[0].y(), line[0].z()});
      const Eigen::Vector2d t =
          across[k].norm() > 1e-9 ? Eigen::Vector2d(across[k].head<2>().normalized()) : Eigen::Vector2d::UnitX();
      lines.push_back(sample_chord(s, line[0].head<2>(), line[0].head<2>() + rise * t, chord_tolerance_mm));
      continue;
    }
    for (auto& run : rising_chords_split(line, s, chord_tolerance_mm, rise)) lines.push_back(std::move(run));
  }
  std::erase_if(lines, [](const std::vector<Sample>& l) { return l.size() < 2; });
  std::vector<Pass> out = to_passes(std::move(lines));
  for (const Pass& pass : out) points.clear_along(pass.points);
  return out;
}

}  // namespace millnet::finish::detail
