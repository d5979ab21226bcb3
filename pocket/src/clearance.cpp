// Clearance queries: every wall segment (boundary + islands) is registered in the cells of a
// uniform bucket grid that it passes through; a query within radius c inspects only
// the cells overlapping the query box. No mutable state: queries are safe from OpenMP threads.
#include "geometry_internal.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::pocket {

struct Clearance::Impl {
  Region region;
  double clearance = 0;
  std::vector<Segment> walls;
  Vec2 lo{0, 0};
  double h = 1;                          ///< cell size, mm
  int nx = 1, ny = 1;                    ///< cells
  std::vector<std::vector<int>> cells;   ///< wall indices per cell (row-major, rows = y)
  std::vector<signed char> cell_inside;  ///< for cells no wall touches: 1 inside region, 0 outside; −1 mixed

  [[nodiscard]] int cx(double x) const { return std::clamp(static_cast<int>(std::floor((x - lo.x()) / h)), 0, nx - 1); }
  [[nodiscard]] int cy(double y) const { return std::clamp(static_cast<int>(std::floor((y - lo.y()) / h)), 0, ny - 1); }
  [[nodiscard]] bool in_grid(const Vec2& p) const {
    return p.x() >= lo.x() && p.y() >= lo.y() && p.x() < lo.x() + nx * h && p.y() < lo.y() + ny * h;
  }

  /// Calls f(wall index) for every wall registered in cells overlapping [a, b] (may repeat).
  template <class F>
  bool any_in_box(const Vec2& a, const Vec2& b, F&& f) const {
    const int x0 = cx(a.x()), x1 = cx(b.x()), y0 = cy(a.y()), y1 = cy(b.y());
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (int w : cells[static_cast<std::size_t>(y * nx + x)])
          if (f(w)) return true;
    return false;
  }

  [[nodiscard]] bool inside_region(const Vec2& p) const {
    if (in_grid(p)) {
      const signed char c = cell_inside[static_cast<std::size_t>(cy(p.y()) * nx + cx(p.x()))];
      if (c >= 0) return c == 1;
    } else {
      return false;  // the grid covers every wall, so the region lies inside it
    }
    return inside(region, p);
  }
};

Clearance::Clearance(const Region& region, double clearance_mm) : impl_(std::make_unique<Impl>()) {
  if (!(clearance_mm >= 0) || !std::isfinite(clearance_mm))
    throw Error("Clearance: clearance must be finite and >= 0, got " + std::to_string(clearance_mm));
  Impl& m = *impl_;
  m.region = region;
  m.clearance = clearance_mm;
  for (const Segment& s : segments(region.boundary)) m.walls.push_back(s);
  for (const Loop& l : region.islands)
    for (const Segment& s : segments(l)) m.walls.push_back(s);
  if (m.walls.empty()) throw Error("Clearance: region has no walls");
  std::vector<detail::BBox> boxes;
  detail::BBox all;
  for (const Segment& s : m.walls) {
    boxes.push_back(detail::bbox(s));
    all.lo = all.lo.cwiseMin(boxes.back().lo);
    all.hi = all.hi.cwiseMax(boxes.back().hi);
  }
  // Cell size: about 4 walls' worth of area per cell, not finer than a tenth of the clearance
  // (queries then touch at most ~21² cells), and at most ~4M cells.
  const Vec2 ext = (all.hi - all.lo).cwiseMax(Vec2(1e-6, 1e-6));
  const double wall_cells = std::max(64.0, 4.0 * static_cast<double>(m.walls.size()));
  m.h = std::sqrt(ext.x() * ext.y() / wall_cells);
  // Not coarser than 0.7 × the clearance either: a wall registered in a cell (below) is within the
  // cell's diagonal, 0.99 × the clearance, of every point of it, so a point that keeps the
  // clearance from every wall lies in a cell no wall is registered in, whose side of the walls is
  // known: point_ok never needs the O(walls) inside test. (Not below a million cells' worth: a
  // 1 m pocket and a Ø1 tool keep 24 MB of empty cells, not 200 MB.)
  if (clearance_mm - tol::clear_mm > 1e-3)
    m.h = std::min(m.h, std::max(0.7 * (clearance_mm - tol::clear_mm), std::sqrt(ext.x() * ext.y() / 1e6)));
  m.h = std::max({m.h, clearance_mm / 10, std::sqrt(ext.x() * ext.y() / 4e6), 1e-6});
  m.lo = all.lo - Vec2(m.h, m.h);
  m.nx = static_cast<int>(std::ceil(ext.x() / m.h)) + 2;
  m.ny = static_cast<int>(std::ceil(ext.y() / m.h)) + 2;
  m.cells.assign(static_cast<std::size_t>(m.nx) * static_cast<std::size_t>(m.ny), {});
  // A wall is registered in the cells it passes through (within tol::join_mm), not in every cell
  // of its bounding box: a diagonal line or an arc would otherwise mark cells far from it as wall
  // cells, whose points then need the region's O(walls) inside test (the costly part of point_ok).
  // A point of the wall in a cell is within half the cell's diagonal of its centre, so the test
  // below keeps every such cell. O(Σ bounding-box cells per wall).
  const double reach = m.h * std::sqrt(0.5) + tol::join_mm;
  for (std::size_t w = 0; w < m.walls.size(); ++w) {
    const detail::BBox& b = boxes[w];
    for (int y = m.cy(b.lo.y() - tol::join_mm); y <= m.cy(b.hi.y() + tol::join_mm); ++y)
      for (int x = m.cx(b.lo.x() - tol::join_mm); x <= m.cx(b.hi.x() + tol::join_mm); ++x)
        if (distance(m.walls[w], m.lo + Vec2((x + 0.5) * m.h, (y + 0.5) * m.h)) <= reach)
          m.cells[static_cast<std::size_t>(y * m.nx + x)].push_back(static_cast<int>(w));
  }
  // A cell no wall touches lies entirely on one side of every wall, and so does the segment between
  // the centres of two such cells that share a side: a 4-connected component of wall-free cells is
  // all inside or all outside. One exact test per component: O(cells + components · walls).
  m.cell_inside.assign(m.cells.size(), -1);
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < m.cells.size(); ++start) {
    if (!m.cells[start].empty() || m.cell_inside[start] >= 0) continue;
    const int sx = static_cast<int>(start % static_cast<std::size_t>(m.nx));
    const int sy = static_cast<int>(start / static_cast<std::size_t>(m.nx));
    const signed char status = inside(region, m.lo + Vec2((sx + 0.5) * m.h, (sy + 0.5) * m.h)) ? 1 : 0;
    m.cell_inside[start] = status;
    stack.assign(1, start);
    while (!stack.empty()) {
      const std::size_t k = stack.back();
      stack.pop_back();
      const int x = static_cast<int>(k % static_cast<std::size_t>(m.nx));
      const int y = static_cast<int>(k / static_cast<std::size_t>(m.nx));
      const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[0] >= m.nx || q[1] >= m.ny) continue;
        const std::size_t j = static_cast<std::size_t>(q[1] * m.nx + q[0]);
        if (!m.cells[j].empty() || m.cell_inside[j] >= 0) continue;
        m.cell_inside[j] = status;
        stack.push_back(j);
      }
    }
  }
}

Clearance::~Clearance() = default;
Clearance::Clearance(Clearance&&) noexcept = default;
Clearance& Clearance::operator=(Clearance&&) noexcept = default;

double Clearance::clearance() const { return impl_->clearance; }

double Clearance::wall_distance(const Vec2& p) const {
  const Impl& m = *impl_;
  double best = std::numeric_limits<double>::infinity();
  if (!m.in_grid(p)) {
    for (const Segment& s : m.walls) best = std::min(best, distance(s, p));
    return best;
  }
  // Rings of cells around p: after ring k every unvisited wall is ≥ k·h away.
  const int px = m.cx(p.x()), py = m.cy(p.y());
  const int kmax = std::max(m.nx, m.ny);
  for (int k = 0; k <= kmax; ++k) {
    for (int y = py - k; y <= py + k; ++y) {
      if (y < 0 || y >= m.ny) continue;
      const bool edge_row = (y == py - k || y == py + k);
      for (int x = px - k; x <= px + k; x += (edge_row ? 1 : 2 * std::max(k, 1))) {
        if (x < 0 || x >= m.nx) continue;
        for (int w : m.cells[static_cast<std::size_t>(y * m.nx + x)])
          best = std::min(best, distance(m.walls[static_cast<std::size_t>(w)], p));
      }
    }
    if (best <= k * m.h) break;
  }
  return best;
}

bool Clearance::point_ok(const Vec2& p) const {
  const Impl& m = *impl_;
  const double lim = m.clearance - tol::clear_mm;
  const Vec2 r(m.clearance, m.clearance);
  if (m.any_in_box(p - r, p + r, [&](int w) { return distance(m.walls[static_cast<std::size_t>(w)], p) < lim; }))
    return false;
  return m.inside_region(p);
}

bool Clearance::move_ok(const Vec2& p, const Vec2& q) const {
  // p is inside and the move keeps clear of every wall (q included: its distance is the move's at
  // its end), so it never crosses one: q is inside too, and keeps the clearance. One inside test,
  // not two (the region's winding test is the costly part of a move check).
  if (!point_ok(p)) return false;
  if (impl_->clearance - tol::clear_mm <= 0 && !point_ok(q)) return false;  // no clearance: a move may touch a wall
  return segment_clear(p, q);
}

bool Clearance::segment_clear(const Vec2& p, const Vec2& q) const {
  const Impl& m = *impl_;
  const double lim = m.clearance - tol::clear_mm;
  const Vec2 r(m.clearance, m.clearance);
  return !m.any_in_box(p.cwiseMin(q) - r, p.cwiseMax(q) + r,
                       [&](int w) { return distance(m.walls[static_cast<std::size_t>(w)], p, q) < lim; });
}

}  // namespace millnet::pocket
