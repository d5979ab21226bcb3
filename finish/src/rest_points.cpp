// The design points a rest program is asked to come near (detail::RestPoints): where the regions
// measure rest over the threshold, sampled on a grid inside the kept regions, and which of them
// the pieces kept so far have brought within the threshold.
#include "rest_internal.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace millnet::finish::detail {

RestPoints::RestPoints(const ingest::Mesh& mesh, const RestRegions& regions, const tooling::Cutter& tool,
                       double spacing, double over_mm)
    : tool_(tool), threshold_(regions.threshold_mm), side_(tool.radius() + regions.threshold_mm) {
  if (!regions.material || regions.mask.empty() || !(spacing > 0)) return;
  // Each kept node's cell sampled k × k, k = ⌈cell / spacing⌉ (the sub-points centred in it).
  const int k = std::max(1, static_cast<int>(std::ceil(regions.cell / spacing - 1e-9)));
  const double sub = regions.cell / k;
  const auto kept = static_cast<double>(std::count(regions.mask.begin(), regions.mask.end(), std::uint8_t{2}));
  if (!(kept * k * k <= tol::rest_points_max)) return;  // too many: not followed
  const DropCutter probe(mesh, tooling::Cutter::ball(0.01));
  std::vector<std::vector<Eigen::Vector3d>> rows(static_cast<std::size_t>(regions.ny)),
      row_normals(static_cast<std::size_t>(regions.ny));
#pragma omp parallel for schedule(dynamic, 4)
  for (int i = 0; i < regions.ny; ++i)  // O(kept nodes · k²) drops
    for (int j = 0; j < regions.nx; ++j) {
      if (regions.mask[static_cast<std::size_t>(i) * static_cast<std::size_t>(regions.nx) +
                       static_cast<std::size_t>(j)] != 2)
        continue;
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
          const double x = regions.x0 + j * regions.cell + (b - 0.5 * (k - 1)) * sub,
                       y = regions.y0 + i * regions.cell + (a - 0.5 * (k - 1)) * sub;
          const CLPoint c = probe.drop(x, y);
          if (c.contact == Contact::None || c.triangle < 0) continue;
          const Eigen::Vector3d n = unit_normal(mesh, c.triangle);
          if (regions.material(c.cc, n) > over_mm) {
            rows[static_cast<std::size_t>(i)].push_back(c.cc);
            row_normals[static_cast<std::size_t>(i)].push_back(n);
          }
        }
    }
  for (std::size_t i = 0; i < rows.size(); ++i) {  // in row order: any thread count
    points_.insert(points_.end(), rows[i].begin(), rows[i].end());
    normals_.insert(normals_.end(), row_normals[i].begin(), row_normals[i].end());
  }
  if (points_.empty()) return;
  // Buckets of side R + threshold over the points' box.
  x0_ = points_.front().x(), y0_ = points_.front().y();
  double xmax = x0_, ymax = y0_;
  for (const Eigen::Vector3d& p : points_) {  // O(points)
    x0_ = std::min(x0_, p.x()), y0_ = std::min(y0_, p.y());
    xmax = std::max(xmax, p.x()), ymax = std::max(ymax, p.y());
  }
  nx_ = static_cast<int>(std::floor((xmax - x0_) / side_)) + 1;
  ny_ = static_cast<int>(std::floor((ymax - y0_) / side_)) + 1;
  buckets_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  for (std::size_t n = 0; n < points_.size(); ++n) buckets_[bucket(points_[n])].push_back(n);
  cleared_.assign(points_.size(), 0);
}

std::size_t RestPoints::bucket(const Eigen::Vector3d& p) const {
  const int i = std::clamp(static_cast<int>(std::floor((p.y() - y0_) / side_)), 0, ny_ - 1),
            j = std::clamp(static_cast<int>(std::floor((p.x() - x0_) / side_)), 0, nx_ - 1);
  return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(j);
}

template <class Visit>
void RestPoints::near(const Eigen::Vector3d& tip, Visit&& visit) const {
  if (buckets_.empty()) return;
  const int bi = static_cast<int>(std::floor((tip.y() - y0_) / side_)),
            bj = static_cast<int>(std::floor((tip.x() - x0_) / side_));
  for (int i = std::max(0, bi - 1); i <= std::min(ny_ - 1, bi + 1); ++i)  // O(points within R + threshold)
    for (int j = std::max(0, bj - 1); j <= std::min(nx_ - 1, bj + 1); ++j)
      for (const std::size_t k :
           buckets_[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(j)])
        if (!cleared_[k] && tool_.distance_to_solid(tip.x(), tip.y(), tip.z(), points_[k].x(), points_[k].y(),
                                                    points_[k].z()) <= threshold_)
          if (!visit(k)) return;
}

std::vector<std::size_t> RestPoints::uncleared() const {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < cleared_.size(); ++k)  // O(points)
    if (!cleared_[k]) out.push_back(k);
  return out;
}

std::size_t RestPoints::clear_at(const Eigen::Vector3d& tip) {
  std::size_t n = 0;
  near(tip, [&](std::size_t k) {
    cleared_[k] = 1;
    ++n;
    return true;
  });
  return n;
}

std::size_t RestPoints::count_at(const Eigen::Vector3d& tip) const {
  std::size_t n = 0;
  near(tip, [&](std::size_t) { return ++n > 0; });
  return n;
}

bool RestPoints::needed(const Eigen::Vector3d& tip) const {
  bool any = false;
  near(tip, [&](std::size_t) { return !(any = true); });
  return any;
}

void RestPoints::clear_along(const std::vector<Eigen::Vector3d>& path) {
  if (buckets_.empty()) return;
  // Placements R/16 apart: the distance to a ball's centre between two of them exceeds the least
  // by at most (R/32)² / (2·R), a thousandth of R.
  const double spacing = tool_.radius() / 16;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {  // O(length / spacing · points near)
    const Eigen::Vector3d &a = path[i], &b = path[i + 1];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int t = (i == 0 ? 0 : 1); t <= steps; ++t) clear_at(a + (b - a) * (static_cast<double>(t) / steps));
  }
}

}  // namespace millnet::finish::detail
