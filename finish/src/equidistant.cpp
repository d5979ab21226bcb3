// Equidistant (3D-offset) passes, strategy 5: level sets of the surface distance from the
// machining boundary.
//
// The distance T solves the eikonal equation |∇T| = √(1 + |∇z|²) on the CL height field z (grid
// ≤ p_f/2, central differences), T = 0 on the boundary, by first-order fast marching (binary heap,
// ties by node index: deterministic). This is the isotropic approximation of the surface metric:
// exact across the slope (where the 3D stepover matters) and along flat ground, an overestimate of
// the in-plane distance elsewhere. Passes are the contours T = k·p_f (k ≥ 0, the first just inside
// the boundary), interpolated on the grid, each contour point dropped exactly and the chords
// between them subdivided like a raster pass.
#include "contours.hpp"
#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace millnet::finish::detail {
namespace {

std::vector<double> fast_marching(const GridSpec& g, const std::vector<double>& z, const std::vector<char>& source) {
  const auto nx = static_cast<std::size_t>(g.nx), ny = static_cast<std::size_t>(g.ny);
  const double inf = std::numeric_limits<double>::infinity();
  auto at = [&](std::size_t i, std::size_t j) { return z[i * nx + j]; };
  // Slowness from central differences (one-sided on the border).
  std::vector<double> slow(nx * ny);
  for (std::size_t i = 0; i < ny; ++i)
    for (std::size_t j = 0; j < nx; ++j) {
      const std::size_t jl = j > 0 ? j - 1 : j, jr = j + 1 < nx ? j + 1 : j;
      const std::size_t id = i > 0 ? i - 1 : i, iu = i + 1 < ny ? i + 1 : i;
      const double gx = (at(i, jr) - at(i, jl)) / (g.step * static_cast<double>(jr - jl));
      const double gy = (at(iu, j) - at(id, j)) / (g.step * static_cast<double>(iu - id));
      slow[i * nx + j] = std::sqrt(1 + gx * gx + gy * gy);
    }
  std::vector<double> T(nx * ny, inf);
  std::vector<char> done(nx * ny, 0);
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  for (std::size_t i = 0; i < ny; ++i)
    for (std::size_t j = 0; j < nx; ++j)
      if (i == 0 || j == 0 || i + 1 == ny || j + 1 == nx || (!source.empty() && source[i * nx + j] != 0)) {
        T[i * nx + j] = 0;
        heap.emplace(0.0, i * nx + j);
      }
  auto update = [&](std::size_t i, std::size_t j) {
    const std::size_t k = i * nx + j;
    if (done[k]) return;
    double a = inf, b = inf;
    if (j > 0 && done[k - 1]) a = std::min(a, T[k - 1]);
    if (j + 1 < nx && done[k + 1]) a = std::min(a, T[k + 1]);
    if (i > 0 && done[k - nx]) b = std::min(b, T[k - nx]);
    if (i + 1 < ny && done[k + nx]) b = std::min(b, T[k + nx]);
    const double h = g.step * slow[k];
    double t;
    if (std::isinf(a) || std::isinf(b) || std::abs(a - b) >= h) {
      t = std::min(a, b) + h;
    } else {
      t = 0.5 * (a + b + std::sqrt(2 * h * h - (a - b) * (a - b)));
    }
    if (t < T[k]) {
      T[k] = t;
      heap.emplace(t, k);
    }
  };
  while (!heap.empty()) {
    const auto [t, k] = heap.top();
    heap.pop();
    if (done[k] || t > T[k]) continue;
    done[k] = 1;
    const std::size_t i = k / nx, j = k % nx;
    if (j > 0) update(i, j - 1);
    if (j + 1 < nx) update(i, j + 1);
    if (i > 0) update(i - 1, j);
    if (i + 1 < ny) update(i + 1, j);
  }
  return T;
}

}  // namespace

std::vector<std::vector<std::vector<Sample>>> equidistant_loops(const Sampler& s, const Box& box, const FinishParams& p,
                                                                bool from_polygons) {
  const double g = std::min(tol::equidistant_grid_mm, p.stepover_mm / 2);
  const GridSpec grid = GridSpec::over(box.x0, box.y0, box.x1, box.y1, g);
  const std::vector<double> cl = cl_heights(s, grid.x0, grid.y0, grid.x1, grid.y1, grid.step, grid.nx, grid.ny);
  std::vector<char> source;
  if (from_polygons && !p.boundary.polygons.empty()) {
    source.assign(cl.size(), 0);
    for (int i = 0; i < grid.ny; ++i)  // O(nodes · polygon points)
      for (int j = 0; j < grid.nx; ++j) {
        const Eigen::Vector2d q = grid.node(i, j);
        source[static_cast<std::size_t>(i) * static_cast<std::size_t>(grid.nx) + static_cast<std::size_t>(j)] =
            p.boundary.encloses(q.x(), q.y()) ? 0 : 1;
      }
  }
  const std::vector<double> T = fast_marching(grid, cl, source);
  const double t_max = *std::max_element(T.begin(), T.end());
  std::vector<double> levels;
  for (int k = 0;; ++k) {
    const double t = k == 0 ? 1e-9 : k * p.stepover_mm;
    if (!(t < t_max)) break;
    levels.push_back(t);
  }
  const double h0 = std::min(tol::initial_sample_mm, s.cutter().radius() / 4);
  std::vector<std::vector<std::vector<Sample>>> out(levels.size());
  const IsoField field(grid, T);
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(levels.size()); ++k) {
    const double level = levels[static_cast<std::size_t>(k)];
    auto place = [level](const Eigen::Vector2d& in, const Eigen::Vector2d& outp, double v_in, double v_out, bool) {
      const double t = std::isfinite(v_out) ? (v_in - level) / (v_in - v_out) : 0.0;
      return std::pair<Eigen::Vector2d, double>(in + t * (outp - in), 0.0);
    };
    for (const auto& loop : field.contours(level, place)) {
      std::vector<Sample> pts;
      for (std::size_t i = 0; i + 1 < loop.size(); ++i) {
        auto seg = sample_segment(s, loop[i].xy, loop[i + 1].xy, std::max(h0, (loop[i + 1].xy - loop[i].xy).norm()),
                                  p.chord_tolerance_mm);
        if (!pts.empty()) seg.erase(seg.begin());
        pts.insert(pts.end(), seg.begin(), seg.end());
      }
      if (pts.size() > 2) {
        pts.back() = pts.front();  // exactly closed
        out[static_cast<std::size_t>(k)].push_back(std::move(pts));
      }
    }
  }
  return out;
}

}  // namespace millnet::finish::detail
