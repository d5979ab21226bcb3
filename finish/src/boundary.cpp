// The machining boundary: polygons (even-odd), the part's silhouette and the tip's Z range as a test
// on CL points, and passes clipped to it on their own segments.
#include "boundary.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace millnet::finish::detail {
namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Grid entries a triangle set would take at cell size `cell` (each triangle in the cells its box
/// overlaps). O(T).
double entries_at(const std::vector<std::array<double, 4>>& boxes, double x0, double y0, double cell) {
  double n = 0;
  for (const auto& b : boxes)
    n += (std::floor((b[2] - x0) / cell) - std::floor((b[0] - x0) / cell) + 1) *
         (std::floor((b[3] - y0) / cell) - std::floor((b[1] - y0) / cell) + 1);
  return n;
}

}  // namespace

}  // namespace millnet::finish::detail

namespace millnet::finish {

bool Boundary::encloses(double x, double y) const {
  if (polygons.empty()) return true;
  bool in = false;
  for (const auto& poly : polygons)  // even-odd over every edge: O(polygon points)
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      const Eigen::Vector2d& a = poly[i];
      const Eigen::Vector2d& b = poly[j];
      if ((a.y() > y) != (b.y() > y) && x < (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
    }
  return in;
}

}  // namespace millnet::finish

namespace millnet::finish::detail {

Fence::Fence(const ingest::Mesh& mesh, const Boundary& b)
    : z_min_(b.z_min), z_max_(b.z_max), on_part_(b.on_part || !b.triangles.empty()) {
  if (!b.triangles.empty() && b.triangles.size() != static_cast<std::size_t>(mesh.F.rows()))
    throw Error("finish: the machining boundary selects among " + std::to_string(b.triangles.size()) +
                " triangles, the mesh has " + std::to_string(mesh.F.rows()));
  if (std::isnan(z_min_) || std::isnan(z_max_) || z_min_ > z_max_)
    throw Error("finish: the machining boundary's Z range [" + std::to_string(z_min_) + ", " + std::to_string(z_max_) +
                "] is empty");
  for (std::size_t k = 0; k < b.polygons.size(); ++k) {
    const auto& poly = b.polygons[k];
    if (poly.size() < 3)
      throw Error("finish: machining boundary polygon " + std::to_string(k + 1) + " has " +
                  std::to_string(poly.size()) + " points (at least 3 make a closed outline)");
    for (const Eigen::Vector2d& q : poly)
      if (!q.allFinite())
        throw Error("finish: machining boundary polygon " + std::to_string(k + 1) + " has a non-finite point");
    boundary_.polygons.push_back(poly);
  }
  active_ = !boundary_.polygons.empty() || on_part_ || b.limits_z();
  if (!on_part_) return;
  // 1. The non-vertical faces' projections, counter-clockwise. O(F).
  std::vector<std::array<double, 4>> boxes;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (!b.triangles.empty() && !b.triangles[static_cast<std::size_t>(f)]) continue;  // not selected
    Triangle t;
    for (int k = 0; k < 3; ++k) t.v[static_cast<std::size_t>(k)] = mesh.V.row(mesh.F(f, k)).head<2>().transpose();
    const double area2 = cross2(t.v[1] - t.v[0], t.v[2] - t.v[0]);
    const double scale = (t.v[1] - t.v[0]).squaredNorm() + (t.v[2] - t.v[0]).squaredNorm();
    if (!(std::abs(area2) > 1e-12 * std::max(scale, 1e-12))) continue;  // vertical (or degenerate)
    if (area2 < 0) std::swap(t.v[1], t.v[2]);
    tris_.push_back(t);
    boxes.push_back({std::min({t.v[0].x(), t.v[1].x(), t.v[2].x()}), std::min({t.v[0].y(), t.v[1].y(), t.v[2].y()}),
                     std::max({t.v[0].x(), t.v[1].x(), t.v[2].x()}), std::max({t.v[0].y(), t.v[1].y(), t.v[2].y()})});
  }
  if (tris_.empty()) return;  // nothing is over the part
  // 2. The grid: about one cell per face, coarsened while big faces would list in too many cells.
  double x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  gx0_ = gy0_ = HUGE_VAL;
  for (const auto& bx : boxes) {
    gx0_ = std::min(gx0_, bx[0]), gy0_ = std::min(gy0_, bx[1]);
    x1 = std::max(x1, bx[2]), y1 = std::max(y1, bx[3]);
  }
  gx0_ -= tol::on_part_mm, gy0_ -= tol::on_part_mm, x1 += tol::on_part_mm, y1 += tol::on_part_mm;
  const double w = x1 - gx0_, h = y1 - gy0_, n = static_cast<double>(tris_.size());
  cell_ = std::max({std::sqrt(w * h / n), std::max(w, h) / 4096, 1e-3});
  while (entries_at(boxes, gx0_, gy0_, cell_) > 8 * n + 4096) cell_ *= 2;  // O(T) per round, ≤ 64 rounds
  nx_ = static_cast<std::size_t>(std::floor(w / cell_)) + 1;
  ny_ = static_cast<std::size_t>(std::floor(h / cell_)) + 1;
  // 3. Counting sort into cells (CSR). O(entries).
  auto cells_of = [&](const std::array<double, 4>& bx, auto visit) {
    const auto i0 = static_cast<std::size_t>(std::max(0.0, std::floor((bx[0] - tol::on_part_mm - gx0_) / cell_)));
    const auto j0 = static_cast<std::size_t>(std::max(0.0, std::floor((bx[1] - tol::on_part_mm - gy0_) / cell_)));
    const auto i1 = std::min(nx_ - 1, static_cast<std::size_t>(std::floor((bx[2] + tol::on_part_mm - gx0_) / cell_)));
    const auto j1 = std::min(ny_ - 1, static_cast<std::size_t>(std::floor((bx[3] + tol::on_part_mm - gy0_) / cell_)));
    for (std::size_t j = j0; j <= j1; ++j)
      for (std::size_t i = i0; i <= i1; ++i) visit(j * nx_ + i);
  };
  start_.assign(nx_ * ny_ + 1, 0);
  for (const auto& bx : boxes) cells_of(bx, [&](std::size_t c) { ++start_[c + 1]; });
  for (std::size_t c = 0; c < nx_ * ny_; ++c) start_[c + 1] += start_[c];
  ids_.resize(start_.back());
  std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t t = 0; t < boxes.size(); ++t)
    cells_of(boxes[t], [&](std::size_t c) { ids_[fill[c]++] = static_cast<std::uint32_t>(t); });
}

bool Fence::over_part(double x, double y) const {
  if (tris_.empty()) return false;
  const double fi = std::floor((x - gx0_) / cell_), fj = std::floor((y - gy0_) / cell_);
  if (!(fi >= 0 && fj >= 0 && fi < static_cast<double>(nx_) && fj < static_cast<double>(ny_))) return false;
  const std::size_t c = static_cast<std::size_t>(fj) * nx_ + static_cast<std::size_t>(fi);
  const Eigen::Vector2d p(x, y);
  for (std::size_t k = start_[c]; k < start_[c + 1]; ++k) {  // O(faces listed in the cell)
    const Triangle& t = tris_[ids_[k]];
    bool in = true;
    for (std::size_t e = 0; e < 3 && in; ++e) {
      const Eigen::Vector2d d = t.v[(e + 1) % 3] - t.v[e];
      in = cross2(d, p - t.v[e]) >= -tol::on_part_mm * d.norm();
    }
    if (in) return true;
  }
  return false;
}

bool Fence::in_polygons(double x, double y) const { return boundary_.encloses(x, y); }

bool Fence::inside_xy(double x, double y) const {
  if (!in_polygons(x, y)) return false;
  return !on_part_ || over_part(x, y);
}

Sample Fence::crossing(const Sample& in, const Sample& out) const {
  double lo = 0, hi = 1;
  const double len = (out.p - in.p).norm();
  while ((hi - lo) * len > tol::boundary_crossing_mm) {  // O(log(len / tol))
    const double mid = 0.5 * (lo + hi);
    (inside(in.p + mid * (out.p - in.p)) ? lo : hi) = mid;
  }
  return {in.p + lo * (out.p - in.p), in.slope_deg};
}

std::vector<std::vector<Sample>> Fence::clip(std::vector<std::vector<Sample>> lines) const {
  if (!active_) return lines;
  // Each line on its own (in parallel: a point's test scans the faces of its grid cell), then the
  // pieces in the lines' order: the same passes for any thread count.
  std::vector<std::vector<std::vector<Sample>>> pieces(lines.size());
#pragma omp parallel for schedule(dynamic, 16) if (lines.size() > 1)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lines.size()); ++k)
    pieces[static_cast<std::size_t>(k)] = clip_line(std::move(lines[static_cast<std::size_t>(k)]));
  std::vector<std::vector<Sample>> out;
  for (auto& line_pieces : pieces)  // O(pieces)
    for (std::vector<Sample>& piece : line_pieces) out.push_back(std::move(piece));
  return out;
}

std::vector<std::vector<Sample>> Fence::clip_line(std::vector<Sample> line) const {
  std::vector<std::vector<Sample>> out;
  std::vector<char> in(line.size());
  bool all = true;
  for (std::size_t i = 0; i < line.size(); ++i) all = (in[i] = inside(line[i].p) ? 1 : 0) != 0 && all;  // O(points)
  if (all) {
    out.push_back(std::move(line));
    return out;
  }
  std::vector<std::vector<Sample>> pieces;
  std::vector<Sample> cur;
  if (in[0] != 0) cur.push_back(line[0]);
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (in[i - 1] != 0 && in[i] != 0) {
      cur.push_back(line[i]);
    } else if (in[i - 1] != 0) {  // leaves
      cur.push_back(crossing(line[i - 1], line[i]));
      pieces.push_back(std::move(cur));
      cur.clear();
    } else if (in[i] != 0) {  // comes back
      cur = {crossing(line[i], line[i - 1]), line[i]};
    }
  }
  if (!cur.empty()) pieces.push_back(std::move(cur));
  // A closed loop that starts inside: its last piece runs on into its first.
  if (is_closed(line) && in[0] != 0 && pieces.size() > 1) {
    std::vector<Sample>& last = pieces.back();
    last.insert(last.end(), pieces.front().begin() + 1, pieces.front().end());
    pieces.front() = std::move(last);
    pieces.pop_back();
  }
  for (std::vector<Sample>& piece : pieces)
    if (piece.size() >= 2 && polyline_length(piece) >= tol::min_pass_mm) out.push_back(std::move(piece));
  return out;
}

}  // namespace millnet::finish::detail
