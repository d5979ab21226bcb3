#include "contours.hpp"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace millnet::finish::detail {

GridSpec GridSpec::over(double x0, double y0, double x1, double y1, double step) {
  GridSpec g;
  g.x0 = x0, g.y0 = y0, g.x1 = x1, g.y1 = y1, g.step = step;
  g.nx = static_cast<int>(std::ceil((x1 - x0) / step - 1e-9)) + 1;
  g.ny = static_cast<int>(std::ceil((y1 - y0) / step - 1e-9)) + 1;
  return g;
}

std::vector<std::vector<ContourPoint>> iso_contours(const GridSpec& g, const std::vector<double>& values, double level,
                                                    const PlaceCrossing& place) {
  return IsoField(g, values).contours(level, place);
}

// Cells (i, j), i in [−1, ny), j in [−1, nx), have the corners (i, j), (i, j + 1), (i + 1, j + 1),
// (i + 1, j); run r of row i holds the cells j = −1 + r·kRun … −1 + (r + 1)·kRun − 1.
IsoField::IsoField(const GridSpec& g, const std::vector<double>& values, bool skip_runs) : g_(g), values_(values) {
  constexpr double kOut = -std::numeric_limits<double>::infinity();
  auto value = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= g.ny || j >= g.nx) return kOut;
    const double v = values[static_cast<std::size_t>(i) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(j)];
    return std::isnan(v) ? kOut : v;
  };
  runs_ = (g.nx + 1 + kRun - 1) / kRun;
  const auto n = static_cast<std::size_t>(g.ny + 1) * static_cast<std::size_t>(runs_);
  lo_.assign(n, std::numeric_limits<double>::infinity());
  hi_.assign(n, kOut);
  if (!skip_runs) {  // bounds that never skip
    lo_.assign(n, kOut);
    hi_.assign(n, std::numeric_limits<double>::infinity());
    return;
  }
  for (int i = -1; i < g.ny; ++i)  // O(nodes): each node in ≤ 2 rows × 2 runs
    for (int r = 0; r < runs_; ++r) {
      const std::size_t b =
          static_cast<std::size_t>(i + 1) * static_cast<std::size_t>(runs_) + static_cast<std::size_t>(r);
      const int j0 = -1 + r * kRun, j1 = std::min(g.nx, j0 + kRun);  // corner columns j0 … j1
      for (int di = 0; di <= 1; ++di)
        for (int j = j0; j <= j1; ++j) {
          const double v = value(i + di, j);
          lo_[b] = std::min(lo_[b], v);
          hi_[b] = std::max(hi_[b], v);
        }
    }
}

std::vector<std::vector<ContourPoint>> IsoField::contours(double level, const PlaceCrossing& place) const {
  const GridSpec& g = g_;
  const std::vector<double>& values = values_;
  const int W = g.nx + 2;  // padded width: node (i, j) ↦ (i + 1, j + 1), the ring is outside
  auto value = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= g.ny || j >= g.nx) return -std::numeric_limits<double>::infinity();
    return values[static_cast<std::size_t>(i) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(j)];
  };
  auto pad = [&](int i, int j) { return i < 0 || j < 0 || i >= g.ny || j >= g.nx; };
  auto edge_id = [&](int i, int j, bool vertical) {
    return (static_cast<std::int64_t>(i + 1) * W + (j + 1)) * 2 + (vertical ? 1 : 0);
  };
  struct Crossing {
    std::int64_t id;
    int ii, ij, oi, oj;  // inside node, outside node
  };
  struct Segment {
    std::int64_t from, to;
  };
  std::vector<Crossing> crossings;
  std::unordered_map<std::int64_t, std::size_t> crossing_of;
  std::vector<Segment> segments;
  auto add_crossing = [&](std::int64_t id, int ai, int aj, int bi, int bj, bool a_in) {
    if (crossing_of.count(id)) return;
    crossing_of.emplace(id, crossings.size());
    if (a_in)
      crossings.push_back({id, ai, aj, bi, bj});
    else
      crossings.push_back({id, bi, bj, ai, aj});
  };
  for (int i = -1; i < g.ny; ++i) {
    for (int j = -1; j < g.nx; ++j) {
      if ((j + 1) % kRun == 0) {  // the first cell of a run: skip the run if no cell of it can cross
        const std::size_t b = static_cast<std::size_t>(i + 1) * static_cast<std::size_t>(runs_) +
                              static_cast<std::size_t>((j + 1) / kRun);
        if (hi_[b] < level || lo_[b] >= level) {
          j += kRun - 1;
          continue;
        }
      }
      // Corners CCW: a (i,j), b (i,j+1), c (i+1,j+1), d (i+1,j).
      const std::array<int, 4> ci{i, i, i + 1, i + 1};
      const std::array<int, 4> cj{j, j + 1, j + 1, j};
      std::array<double, 4> v{};
      std::array<bool, 4> in{};
      int n_in = 0;
      for (int k = 0; k < 4; ++k) {
        v[static_cast<std::size_t>(k)] = value(ci[static_cast<std::size_t>(k)], cj[static_cast<std::size_t>(k)]);
        in[static_cast<std::size_t>(k)] = v[static_cast<std::size_t>(k)] >= level;
        n_in += in[static_cast<std::size_t>(k)] ? 1 : 0;
      }
      if (n_in == 0 || n_in == 4) continue;
      // Edge k runs from corner k to corner k+1; its id is that of the grid edge it lies on.
      const std::array<std::int64_t, 4> eid{edge_id(i, j, false), edge_id(i, j + 1, true), edge_id(i + 1, j, false),
                                            edge_id(i, j, true)};
      std::array<int, 4> kind{};  // +1 in→out, −1 out→in, 0 none
      for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t k1 = (k + 1) % 4;
        if (in[k] == in[k1]) continue;
        kind[k] = in[k] ? 1 : -1;
        add_crossing(eid[k], ci[k], cj[k], ci[k1], cj[k1], in[k]);
      }
      const bool saddle = n_in == 2 && in[0] == in[2];
      if (!saddle) {
        std::int64_t from = 0, to = 0;
        for (std::size_t k = 0; k < 4; ++k) {
          if (kind[k] == 1) from = eid[k];
          if (kind[k] == -1) to = eid[k];
        }
        segments.push_back({from, to});
        continue;
      }
      const double centre = 0.25 * (v[0] + v[1] + v[2] + v[3]);
      const bool centre_in = centre >= level;
      for (std::size_t k = 0; k < 4; ++k) {
        if (kind[k] != 1) continue;
        const std::size_t m = centre_in ? (k + 1) % 4 : (k + 3) % 4;
        segments.push_back({eid[k], eid[m]});
      }
    }
  }
  // Place every crossing (possibly expensive: the waterline refines with the drop-cutter).
  std::vector<ContourPoint> at(crossings.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(crossings.size()); ++c) {
    const Crossing& x = crossings[static_cast<std::size_t>(c)];
    const bool p = pad(x.oi, x.oj);
    const Eigen::Vector2d a = g.node(x.ii, x.ij), b = g.node(x.oi, x.oj);
    const auto [xy, aux] = place(a, b, value(x.ii, x.ij), value(x.oi, x.oj), p);
    at[static_cast<std::size_t>(c)] = {xy, aux, p};
  }
  // Chain: each crossing starts one segment and ends another.
  std::unordered_map<std::int64_t, std::size_t> starting;
  starting.reserve(segments.size());
  for (std::size_t s = 0; s < segments.size(); ++s) starting.emplace(segments[s].from, s);
  std::vector<char> used(segments.size(), 0);
  std::vector<std::vector<ContourPoint>> loops;
  for (std::size_t s0 = 0; s0 < segments.size(); ++s0) {
    if (used[s0]) continue;
    std::vector<ContourPoint> loop;
    std::size_t s = s0;
    while (!used[s]) {
      used[s] = 1;
      loop.push_back(at[crossing_of.at(segments[s].from)]);
      const auto next = starting.find(segments[s].to);
      if (next == starting.end()) break;  // cannot happen on a padded grid
      s = next->second;
    }
    if (loop.size() >= 3) {
      loop.push_back(loop.front());
      loops.push_back(std::move(loop));
    }
  }
  return loops;
}

}  // namespace millnet::finish::detail
