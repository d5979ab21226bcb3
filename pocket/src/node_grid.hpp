#pragma once
// The SOM's ring nodes in a uniform grid, for the winner search (the nearest node to a tool point)
// while the nodes move.
//
//   contract  nearest(q) is the node at the smallest squared distance to q, the smallest index on
//             ties: exactly what a scan of every node gives (tests/pocket/test_som.cpp checks it
//             against that scan while nodes move);
//   cost      insert and move O(1); nearest scans rings of cells around q's cell until the next
//             ring's lower bound exceeds the best distance: O(cells within the nearest distance),
//             O(1) once the ring has spread over the tool points. Until then a query far from the
//             ring scans O((distance / cell)²) empty cells; a pyramid of node counts over the grid
//             (best-first descent, O(levels) per query) was tried against it and was 1.6× slower on
//             bench_som's 1k–100k points (its counts are updated at every cell change of every
//             pulled node), so the rings stay (issue 42).
#include "millnet/pocket/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace millnet::pocket::detail {

class NodeGrid {
public:
  NodeGrid(const Vec2& lo, const Vec2& hi, std::size_t target_cells) : lo_(lo) {
    const double wdt = std::max(hi.x() - lo.x(), 0.0), hgt = std::max(hi.y() - lo.y(), 0.0);
    const double tc = static_cast<double>(std::max<std::size_t>(target_cells, 1));
    double s = std::sqrt(wdt * hgt / tc);
    s = std::max({s, std::max(wdt, hgt) / tc, 1e-12});
    s_ = s;
    inv_s_ = 1.0 / s;
    nx_ = static_cast<int>(std::floor(wdt / s)) + 1;
    ny_ = static_cast<int>(std::floor(hgt / s)) + 1;
    cells_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  }

  void insert(int j, const Vec2& p) {
    if (cell_of_.size() <= static_cast<std::size_t>(j)) {
      cell_of_.resize(static_cast<std::size_t>(j) + 1, -1);
      slot_of_.resize(static_cast<std::size_t>(j) + 1, 0);
    }
    const int c = cell(p);
    auto& v = cells_[static_cast<std::size_t>(c)];
    cell_of_[static_cast<std::size_t>(j)] = c;
    slot_of_[static_cast<std::size_t>(j)] = v.size();
    v.push_back(j);
  }

  /// Node j moved to p: O(1).
  void moved(int j, const Vec2& p) {
    const int c = cell(p);
    const int old = cell_of_[static_cast<std::size_t>(j)];
    if (c == old) return;
    auto& v = cells_[static_cast<std::size_t>(old)];
    const std::size_t slot = slot_of_[static_cast<std::size_t>(j)];
    const int last = v.back();
    v[slot] = last;
    slot_of_[static_cast<std::size_t>(last)] = slot;
    v.pop_back();
    auto& w = cells_[static_cast<std::size_t>(c)];
    cell_of_[static_cast<std::size_t>(j)] = c;
    slot_of_[static_cast<std::size_t>(j)] = w.size();
    w.push_back(j);
  }

  /// Nearest node to q (smallest index on ties), {-1, inf} when no node is at a finite distance
  /// (callers turn that into an error).
  std::pair<int, double> nearest(const Vec2& q, const std::vector<Vec2>& nodes) const {
    const int cx = std::clamp(static_cast<int>(std::floor((q.x() - lo_.x()) * inv_s_)), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>(std::floor((q.y() - lo_.y()) * inv_s_)), 0, ny_ - 1);
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    const int rmax = std::max(nx_, ny_);
    for (int r = 0; r <= rmax; ++r) {
      if (r > 0) {
        // distance from q to the outside of the (2r−1)² block of cells already scanned
        const double x0 = lo_.x() + (cx - r + 1) * s_, x1 = lo_.x() + (cx + r) * s_;
        const double y0 = lo_.y() + (cy - r + 1) * s_, y1 = lo_.y() + (cy + r) * s_;
        const double lb = std::min({q.x() - x0, x1 - q.x(), q.y() - y0, y1 - q.y()});
        if (best >= 0 && lb > 0 && lb * lb > bd) break;
        if (cx - r < 0 && cy - r < 0 && cx + r >= nx_ && cy + r >= ny_) break;
      }
      const int ylo = std::max(cy - r, 0), yhi = std::min(cy + r, ny_ - 1);
      for (int y = ylo; y <= yhi; ++y) {
        const bool edge_row = (y == cy - r || y == cy + r);
        const int step = edge_row ? 1 : 2 * r;
        for (int x = cx - r; x <= cx + r; x += std::max(step, 1)) {
          if (x < 0 || x >= nx_) continue;
          scan_cell(y * nx_ + x, q, nodes, best, bd);
        }
      }
    }
    return {best, bd};
  }

private:
  void scan_cell(int c, const Vec2& q, const std::vector<Vec2>& nodes, int& best, double& bd) const {
    for (int j : cells_[static_cast<std::size_t>(c)]) {
      const double d = (nodes[static_cast<std::size_t>(j)] - q).squaredNorm();
      if (d < bd || (d == bd && j < best)) {
        bd = d;
        best = j;
      }
    }
  }

  int cell(const Vec2& p) const {
    // nodes never leave the grid's box (convex combinations), so truncation is a floor here
    const int x = std::min(static_cast<int>((p.x() - lo_.x()) * inv_s_), nx_ - 1);
    const int y = std::min(static_cast<int>((p.y() - lo_.y()) * inv_s_), ny_ - 1);
    return y * nx_ + x;
  }

  Vec2 lo_;
  double s_ = 1, inv_s_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<int> cell_of_;
  std::vector<std::size_t> slot_of_;
};

}  // namespace millnet::pocket::detail
