// The stock a simulation left, as rest.hpp reads it (RestStock), and the exact area a tool cannot
// reach (unreachable_regions: a point-like probe's rest behind it), and the rest program's passes
// cut to where they remove rest (detail::trim_to_rest) and, machined in order on a copy of the
// stock, to where they cut (detail::cut_pieces).
#include "rest_internal.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace millnet::finish {
namespace {

void require_stock(bool ok, const std::string& key, const std::string& what) {
  if (!ok) throw Error("rest: " + key + " " + what);
}

/// visit(cx, cy, d, h) for each cell of `st` whose centre (cx, cy) lies within r of (x, y) (d its
/// distance, h its height). O((r / cell)²).
template <class Stock, class Visit>
void cells_within(Stock& st, double x, double y, double r, Visit&& visit) {
  const int j0 = std::max(0, static_cast<int>(std::floor((x - r - st.x0) / st.cell))),
            j1 = std::min(st.nx - 1, static_cast<int>(std::ceil((x + r - st.x0) / st.cell)));
  const int i0 = std::max(0, static_cast<int>(std::floor((y - r - st.y0) / st.cell))),
            i1 = std::min(st.ny - 1, static_cast<int>(std::ceil((y + r - st.y0) / st.cell)));
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const double cx = st.x0 + j * st.cell, cy = st.y0 + i * st.cell, d = std::hypot(cx - x, cy - y);
      if (d <= r)
        visit(cx, cy, d,
              st.z[static_cast<std::size_t>(i) * static_cast<std::size_t>(st.nx) + static_cast<std::size_t>(j)]);
    }
}

}  // namespace

void RestStock::check() const {
  require_stock(nx > 0 && ny > 0 && z.size() == static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), "stock",
                "must hold nx·ny heights (" + std::to_string(nx) + " × " + std::to_string(ny) + ", got " +
                    std::to_string(z.size()) + ")");
  require_stock(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(cell) && cell > 0 && std::isfinite(z_offset),
                "stock", "needs a finite origin and offset and a cell > 0");
  require_stock(std::all_of(z.begin(), z.end(), [](double v) { return std::isfinite(v); }), "stock",
                "heights must be finite");
  require_stock((exact_mm.empty() && exact_z.empty()) || (exact_mm.size() == z.size() && exact_z.size() == z.size()),
                "stock",
                "exact measures must be none or one per cell (" + std::to_string(z.size()) + ", got " +
                    std::to_string(exact_mm.size()) + " and " + std::to_string(exact_z.size()) + ")");
}

double RestStock::height(double x, double y) const {
  const double u = (x - x0) / cell, v = (y - y0) / cell;
  if (!(u >= 0 && v >= 0 && u <= nx - 1 && v <= ny - 1)) return -std::numeric_limits<double>::infinity();
  const int j0 = std::min(static_cast<int>(u), std::max(nx - 2, 0)),
            i0 = std::min(static_cast<int>(v), std::max(ny - 2, 0));
  const int j1 = std::min(j0 + 1, nx - 1), i1 = std::min(i0 + 1, ny - 1);
  const double fu = u - j0, fv = v - i0;
  auto at = [&](int i, int j) {
    return z[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)];
  };
  return z_offset + (1 - fv) * ((1 - fu) * at(i0, j0) + fu * at(i0, j1)) +
         fv * ((1 - fu) * at(i1, j0) + fu * at(i1, j1));
}

double RestStock::material(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  return material_over(p, n, -std::numeric_limits<double>::infinity());
}

double RestStock::material_over(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double floor_mm) const {
  // Measured exactly at the nearest cell's design point, where that lies on p's surface.
  if (!exact_mm.empty()) {
    const long j = std::lround((p.x() - x0) / cell), i = std::lround((p.y() - y0) / cell);
    if (i >= 0 && j >= 0 && i < ny && j < nx) {
      const auto c = static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j);
      const Eigen::Vector3d q(x0 + static_cast<double>(j) * cell, y0 + static_cast<double>(i) * cell,
                              exact_z[c] + z_offset);
      if (!std::isnan(exact_mm[c]) && std::abs(n.dot(q - p)) <= 0.5 * cell) return exact_mm[c];
    }
  }
  // Along the normal from p: how far until the point is above the stock (in the air)?
  auto in = [&](double t) { return height(p.x() + t * n.x(), p.y() + t * n.y()) - (p.z() + t * n.z()); };
  if (!(in(0) > 0)) return 0.0;
  // A wall's place in the columns is known to half a cell: the ray's length less that.
  const double known = 0.5 * cell * std::hypot(n.x(), n.y());
  const double cap = 64 * cell;
  double lo = 0, hi = cell / 4;
  while (in(hi) > 0) {  // O(log(cap / cell)) steps out
    if (hi >= cap) return cap;
    lo = hi;
    hi = std::min(2 * hi, cap);
  }
  // Bisection to (hi − lo) / 65536; the answer lies in (lo, hi) less `known`, so once all of that
  // is at most floor_mm the rest of the steps cannot lift it over.
  for (int k = 0; k < 16; ++k) {
    if (hi - known <= floor_mm) return std::max(0.0, std::min(floor_mm, 0.5 * (lo + hi) - known));
    const double mid = 0.5 * (lo + hi);
    (in(mid) > 0 ? lo : hi) = mid;
  }
  return std::max(0.0, 0.5 * (lo + hi) - known);
}

double RestStock::clearing_tip(const tooling::Cutter& tool, double x, double y) const {
  // Each cell at its corner nearest the axis: the tool must clear the cell's whole top.
  const double r = tool.radius(), half = cell * std::numbers::sqrt2 / 2;
  const double reach = r + cell;
  if (!(x >= x0 - reach && x <= x0 + nx * cell + reach && y >= y0 - reach && y <= y0 + ny * cell + reach))
    return -std::numeric_limits<double>::infinity();  // off the grid (or not finite)
  const int j0 = std::max(0, static_cast<int>(std::floor((x - reach - x0) / cell))),
            j1 = std::min(nx - 1, static_cast<int>(std::ceil((x + reach - x0) / cell)));
  const int i0 = std::max(0, static_cast<int>(std::floor((y - reach - y0) / cell))),
            i1 = std::min(ny - 1, static_cast<int>(std::ceil((y + reach - y0) / cell)));
  if (j0 > j1 || i0 > i1) return -std::numeric_limits<double>::infinity();
  double tip = -std::numeric_limits<double>::infinity();
  for (int i = i0; i <= i1; ++i)  // O((R / cell)²) cells
    for (int j = j0; j <= j1; ++j) {
      const double d = std::hypot(x0 + j * cell - x, y0 + i * cell - y) - half;
      if (d > r) continue;
      const double h = z[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)];
      tip = std::max(tip, h - tool.profile_height(std::max(d, 0.0)));
    }
  return tip == -std::numeric_limits<double>::infinity() ? tip : tip + z_offset;
}

double RestStock::engagement(const tooling::Cutter& tool, double x, double y, double tip) const {
  const double top = tip - z_offset;  // in the grid's heights
  double most = 0;
  cells_within(*this, x, y, tool.radius(), [&](double, double, double d, double h) {  // O((R / cell)²)
    if (std::isfinite(h) && h > top + tool.profile_height(d)) most = std::max(most, h - top);
  });
  return most;
}

namespace {

/// How far a column of material standing `hr` above the tip of `tool`, `d` from its axis, reaches
/// into the tool's solid normal to its surface: under the flat bottom the height (or the distance
/// to the side, when less), beside the corner the corner radius less the distance from the
/// corner's centre to the column. ≤ 0 when the column is clear of the tool.
double depth_into(const tooling::Cutter& tool, double d, double hr) {
  const double r = tool.radius(), rc = tool.profile_corner_radius(), a = r - rc;
  if (d <= a) return std::min(hr, r - d);
  return rc - std::hypot(d - a, std::max(0.0, rc - hr));
}

}  // namespace

Removal RestStock::removal(const tooling::Cutter& tool, double x, double y, double tip) const {
  return removal_behind(tool, Eigen::Vector3d(x, y, tip), nullptr, 0);
}

Removal RestStock::removal_behind(const tooling::Cutter& tool, const Eigen::Vector3d& p, const Eigen::Vector3d* before,
                                  std::size_t n) const {
  const double r = tool.radius(), top = p.z() - z_offset;
  thread_local std::vector<Eigen::Vector3d> near;  // the placements that may share a cell with this one
  near.clear();
  for (std::size_t k = 0; k < n; ++k)  // O(n)
    if ((before[k].head<2>() - p.head<2>()).squaredNorm() <= 4 * r * r)
      near.emplace_back(before[k].x(), before[k].y(), before[k].z() - z_offset);
  Removal most;
  cells_within(*this, p.x(), p.y(), r, [&](double cx, double cy, double d, double h) {  // O((R / cell)² · near)
    const double surface = top + tool.profile_height(d);
    // (the placements before only lower a cell, and both figures grow with its height)
    if (!std::isfinite(h) || !(h - surface > most.height || depth_into(tool, d, h - top) > most.thickness)) return;
    for (const Eigen::Vector3d& q : near)
      if (const double dq = std::hypot(cx - q.x(), cy - q.y()); dq <= r)
        h = std::min(h, q.z() + tool.profile_height(dq));
    if (!(h > surface)) return;
    most.height = std::max(most.height, h - surface);
    most.thickness = std::max(most.thickness, depth_into(tool, d, h - top));
  });
  return most;
}

void RestStock::cut(const tooling::Cutter& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (cell / 2))));
  for (int t = 0; t <= n; ++t) {  // O(length / cell) placements
    const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(t) / n);
    const double tip = q.z() - z_offset;
    cells_within(*this, q.x(), q.y(), tool.radius(), [&](double, double, double d, double& h) {  // O((R / cell)²)
      h = std::min(h, tip + tool.profile_height(d));
    });
  }
}

double RestStock::cut_depth(const tooling::Cutter& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (cell / 2))));
  double most = 0;
  for (int t = 0; t <= n; ++t) {  // O(length / cell) placements
    const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(t) / n);
    const double tip = q.z() - z_offset;
    cells_within(*this, q.x(), q.y(), tool.radius(), [&](double, double, double d, double h) {  // O((R / cell)²)
      if (std::isfinite(h)) most = std::max(most, h - (tip + tool.profile_height(d)));
    });
  }
  return most;
}

double unreachable_area_mm2(const ingest::Mesh& mesh, const tooling::Cutter& tool, double threshold_mm) {
  return unreachable_regions(mesh, tool, threshold_mm).rest_axis_area_mm2;
}

RestRegions unreachable_regions(const ingest::Mesh& mesh, const tooling::Cutter& tool, double threshold_mm) {
  RestParams rp;
  rp.reference = tool;
  rp.threshold_mm = threshold_mm;
  rp.margin_mm = 0;
  rp.min_area_mm2 = 0;
  rp.mask_only = true;
  const DropCutter probe(mesh, tooling::Cutter::ball(0.01));
  return rest_regions(mesh, probe, rp);
}

namespace detail {

namespace {

/// What the rest program itself has cut so far: the new tool's placements along the kept pieces
/// (every R/8), bucketed by XY in squares of side R over the regions' box. A design point is
/// cleared when some placement's solid comes within eps of it (distance_to_tool, as the
/// reference's placements are tested) no higher than the top of its profile (the flutes above
/// are not counted on: a small tool's are short). Between placements the tool comes closer than at them, so
/// nothing is taken for cleared that is not.
class SweptByRest {
public:
  SweptByRest(const RestRegions& regions, const tooling::Cutter& tool)
      : tool_(tool), side_(tool.radius()), top_(tool.profile_height(tool.radius())) {
    x0_ = regions.x0 - side_, y0_ = regions.y0 - side_;
    const double w = regions.cell * (regions.nx - 1) + 2 * side_, h = regions.cell * (regions.ny - 1) + 2 * side_;
    if (!((w / side_ + 2) * (h / side_ + 2) <= 1e7)) return;  // too many: the rest program's cuts not followed
    nx_ = static_cast<int>(std::ceil(w / side_)) + 1, ny_ = static_cast<int>(std::ceil(h / side_)) + 1;
    buckets_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  }
  [[nodiscard]] bool cleared(const Eigen::Vector3d& p, double eps) const {
    if (buckets_.empty()) return false;
    const int reach = static_cast<int>(std::ceil((side_ + eps) / side_));
    const int bi = static_cast<int>(std::floor((p.y() - y0_) / side_)),
              bj = static_cast<int>(std::floor((p.x() - x0_) / side_));
    for (int i = std::max(0, bi - reach); i <= std::min(ny_ - 1, bi + reach); ++i)  // O(placements near)
      for (int j = std::max(0, bj - reach); j <= std::min(nx_ - 1, bj + reach); ++j)
        // Latest first (the pass before is the likeliest to have cleared it); the cutting end only,
        // not the flutes above; a tip above the point by more than eps cannot touch it.
        for (auto t = buckets_[at(i, j)].rbegin(); t != buckets_[at(i, j)].rend(); ++t)
          if (p.z() <= t->z() + top_ && p.z() >= t->z() - eps &&
              distance_to_tool(tool_, t->x(), t->y(), t->z(), p) <= eps)
            return true;
    return false;
  }
  void sweep(const Pass& piece) {
    if (buckets_.empty()) return;
    const double spacing = tool_.radius() / 8;
    for (std::size_t i = 0; i + 1 < piece.points.size(); ++i) {  // O(length / spacing)
      const Eigen::Vector3d &a = piece.points[i], &b = piece.points[i + 1];
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
      for (int t = (i == 0 ? 0 : 1); t <= steps; ++t) {
        const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(t) / steps);
        const int bi = static_cast<int>(std::floor((q.y() - y0_) / side_)),
                  bj = static_cast<int>(std::floor((q.x() - x0_) / side_));
        if (bi >= 0 && bj >= 0 && bi < ny_ && bj < nx_) buckets_[at(bi, bj)].push_back(q);
      }
    }
  }

private:
  [[nodiscard]] std::size_t at(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(j);
  }
  tooling::Cutter tool_;
  double side_, top_, x0_ = 0, y0_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<Eigen::Vector3d>> buckets_;
};

/// `st` cut by `tool` along the polyline `path` (RestStock::cut on each segment).
void cut_along(RestStock& st, const tooling::Cutter& tool, const std::vector<Eigen::Vector3d>& path) {
  for (std::size_t i = 0; i + 1 < path.size(); ++i) st.cut(tool, path[i], path[i + 1]);  // O(segments)
}

/// The stock on every k-th cell of each row and column (the cells' centres kept where they are):
/// k² times fewer cells for a test that needs them no closer than k cells apart.
RestStock every_kth_cell(const RestStock& st, int k) {
  if (k <= 1) return st;
  RestStock out;
  out.x0 = st.x0, out.y0 = st.y0, out.cell = st.cell * k, out.z_offset = st.z_offset;
  out.nx = (st.nx - 1) / k + 1, out.ny = (st.ny - 1) / k + 1;
  out.z.resize(static_cast<std::size_t>(out.nx) * static_cast<std::size_t>(out.ny));
  for (int i = 0; i < out.ny; ++i)  // O(cells / k²)
    for (int j = 0; j < out.nx; ++j)
      out.z[static_cast<std::size_t>(i) * static_cast<std::size_t>(out.nx) + static_cast<std::size_t>(j)] =
          st.z[static_cast<std::size_t>(i * k) * static_cast<std::size_t>(st.nx) + static_cast<std::size_t>(j * k)];
  return out;
}

}  // namespace

std::vector<std::vector<Pass>> trim_to_rest(const std::vector<Pass>& passes, const DropCutter& tool,
                                            const ingest::Mesh& mesh, const RestRegions& regions,
                                            std::optional<RestPoints>* left) {
  std::vector<std::vector<Pass>> pieces(passes.size());
  if (!regions.material) {
    for (std::size_t k = 0; k < passes.size(); ++k) pieces[k] = {passes[k]};
    return pieces;
  }
  const double eps = regions.threshold_mm / 2, r = tool.cutter().radius(), run_on = tol::rest_run_on_radii * r;
  const double probe = tol::rest_probe_radii * r, bridge = tol::rest_bridge_radii * r;
  SweptByRest swept(regions, tool.cutter());
  // From a stock: what was left, cut by the pieces kept so far (cells about R/16 apart at most: a
  // crease's rest is 0.1–0.3 mm across; a Ø2 on 0.02 mm cells asks 9× fewer of them). Not behind
  // a reference: its envelope is known near the regions only.
  std::optional<RestStock> running;
  if (regions.left && regions.from_stock)
    running = every_kth_cell(*regions.left,
                             std::max(1, static_cast<int>(std::floor(r / 16 / std::max(regions.left->cell, 1e-9)))));
  const double removes = tol::rest_keep_removal_thresholds * regions.threshold_mm;
  // From a stock: the design points with rest over the threshold, on its cells (RestPoints).
  std::optional<RestPoints> points;
  if (running)
    points.emplace(mesh, regions, tool.cutter(), regions.left->cell, tol::rest_point_thresholds * regions.threshold_mm);
  for (std::size_t k = 0; k < passes.size(); ++k) {  // in order: each pass after what the ones before cut
    const Pass& pass = passes[k];
    const auto& pts = pass.points;
    const std::size_t m = pts.size();
    if (m < 2) continue;
    std::vector<double> s(m, 0.0);  // path length along the pass
    for (std::size_t i = 1; i < m; ++i) s[i] = s[i - 1] + (pts[i] - pts[i - 1]).norm();
    // 1. Probes every R/16 along the pass (its straight segments are the path the machine
    //    follows): where the material left, by the stock and by the passes before, exceeds eps.
    std::vector<double> at;
    for (std::size_t i = 0; i + 1 < m; ++i) {  // O(length / probe)
      const int steps = std::max(1, static_cast<int>(std::ceil((s[i + 1] - s[i]) / probe)));
      for (int t = (i == 0 ? 0 : 1); t <= steps; ++t) at.push_back(s[i] + (s[i + 1] - s[i]) * t / steps);
    }
    auto point_at = [&](double where) {
      const auto it = std::upper_bound(s.begin(), s.end(), where);
      const auto i =
          std::min<std::size_t>(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - s.begin(), 1)), m - 1);
      const double len = s[i] - s[i - 1];
      return Eigen::Vector3d(len > 0 ? pts[i - 1] + (where - s[i - 1]) / len * (pts[i] - pts[i - 1]) : pts[i]);
    };
    std::vector<std::uint8_t> cuts(at.size(), 0);
    const auto probes = static_cast<std::ptrdiff_t>(at.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t t = 0; t < probes; ++t) {  // O(probes) drops, each on its own
      const Eigen::Vector3d q = point_at(at[static_cast<std::size_t>(t)]);
      const CLPoint c = tool.drop(q.x(), q.y());
      if (c.contact == Contact::None || c.triangle < 0) continue;
      Eigen::Vector3d cc = c.cc, n = unit_normal(mesh, c.triangle);
      if (q.z() > c.z + std::max(tol::rest_hanging_mm, eps)) {
        // Hanging above its drop (a Z-level beside a vertical wall): the tool touches the wall at
        // its widest, on the side where the drops rise.
        const double dx = tool.drop(q.x() + probe, q.y()).z - tool.drop(q.x() - probe, q.y()).z,
                     dy = tool.drop(q.x(), q.y() + probe).z - tool.drop(q.x(), q.y() - probe).z;
        const double len = std::hypot(dx, dy);
        if (!(len > 0 && std::isfinite(len))) continue;
        const Eigen::Vector3d u(dx / len, dy / len, 0);
        cc = q + tool.cutter().radius() * u + Eigen::Vector3d(0, 0, tool.cutter().profile_height(r));
        n = -u;
      }
      // At the contact, or (where the tool touches one face of a crease while the rest stands
      // between the two) by what the tool standing there takes off what the pieces before left.
      const bool at_contact = regions.material(cc, n) > eps && !swept.cleared(cc, eps);
      // Or where it comes within the threshold of a design point with rest not yet cleared.
      cuts[static_cast<std::size_t>(t)] =
          at_contact || (running && running->removal(tool.cutter(), q.x(), q.y(), q.z()).thickness > removes) ||
                  (points && points->needed(q))
              ? 1
              : 0;
    }
    // 2. Each cutting probe keeps the run-on on either side; stretches within the bridge are one.
    std::vector<std::pair<double, double>> keep;  // [from, to] in path length, ascending
    for (std::size_t t = 0; t < at.size(); ++t) {
      if (!cuts[t]) continue;
      const double from = std::max(0.0, at[t] - run_on), to = std::min(s[m - 1], at[t] + run_on);
      if (!keep.empty() && from <= keep.back().second + bridge)
        keep.back().second = std::max(keep.back().second, to);
      else
        keep.emplace_back(from, to);
    }
    auto& mine = pieces[k];
    if (keep.size() == 1 && keep.front().first <= 0 && keep.front().second >= s[m - 1]) {
      mine.push_back(pass);  // the whole pass cuts
    } else {
      // 3. The pieces: each stretch's ends on their segments, the vertices between; a closed pass
      //    cut near its seam is one piece across it.
      const bool loop =
          pass.closed && keep.size() >= 2 && keep.front().first + (s[m - 1] - keep.back().second) <= bridge;
      auto piece = [&](double from, double to, Pass& out) {
        out.points.push_back(point_at(from));
        for (std::size_t i = 0; i < m; ++i)  // O(points)
          if (s[i] > from && s[i] < to) out.points.push_back(pts[i]);
        out.points.push_back(point_at(to));
      };
      for (std::size_t j = loop ? 1 : 0; j < keep.size(); ++j) {
        Pass out;
        piece(keep[j].first, keep[j].second, out);
        const bool wraps = loop && j + 1 == keep.size();
        if (wraps) piece(0, keep.front().second, out);  // on across the seam
        if (keep[j].second - keep[j].first + (wraps ? keep.front().second : 0) >= tol::min_pass_mm)
          mine.push_back(std::move(out));
      }
    }
    for (const Pass& piece : mine) {  // O(length / cell · (R / cell)²)
      swept.sweep(piece);
      if (running) cut_along(*running, tool.cutter(), piece.points);
      if (points) points->clear_along(piece.points);
    }
  }
  if (left != nullptr) *left = std::move(points);
  return pieces;
}

RestStock reference_envelope(const tooling::Cutter& reference, const std::vector<double>& ref_cl, double x0, double y0,
                             double h, int nx, int ny, const std::vector<std::uint8_t>& near, double reach_mm,
                             double add_mm) {
  RestStock env;
  env.x0 = x0, env.y0 = y0, env.cell = h, env.nx = nx, env.ny = ny;
  env.z.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), HUGE_VAL);
  auto at = [nx](int i, int j) {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j);
  };
  const int wide = static_cast<int>(std::ceil(reach_mm / h)),
            ref_cells = static_cast<int>(std::ceil(reference.radius() / h));
  std::vector<std::uint8_t> want(env.z.size(), 0);
  for (int i = 0; i < ny; ++i)  // O(near nodes · (reach / h)²)
    for (int j = 0; j < nx; ++j) {
      if (!near[at(i, j)]) continue;
      for (int a = std::max(0, i - wide); a <= std::min(ny - 1, i + wide); ++a)
        for (int b = std::max(0, j - wide); b <= std::min(nx - 1, j + wide); ++b)
          if ((a - i) * (a - i) + (b - j) * (b - j) <= wide * wide) want[at(a, b)] = 1;
    }
#pragma omp parallel for schedule(dynamic, 8)
  for (int i = 0; i < ny; ++i)  // O(wanted nodes · (R / h)²)
    for (int j = 0; j < nx; ++j) {
      if (!want[at(i, j)]) continue;
      double e = HUGE_VAL;  // the lowest of the reference's surfaces over the node
      for (int a = std::max(0, i - ref_cells); a <= std::min(ny - 1, i + ref_cells); ++a)
        for (int b = std::max(0, j - ref_cells); b <= std::min(nx - 1, j + ref_cells); ++b) {
          const double d = h * std::hypot(a - i, b - j);
          if (d <= reference.radius()) e = std::min(e, ref_cl[at(a, b)] + reference.profile_height(d));
        }
      env.z[at(i, j)] = e + add_mm;
    }
  return env;
}

namespace {
/// The stretch [s0, s1] of arc length of the polyline `pts` (cumulative lengths `cum`), lifted by
/// `lift`: its own vertices inside, its ends interpolated. O(points).
Pass stretch_of(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& cum, double s0, double s1,
                double lift) {
  auto at = [&](double t) {
    const auto hi = std::lower_bound(cum.begin(), cum.end(), t);
    if (hi == cum.begin()) return pts.front();
    if (hi == cum.end()) return pts.back();
    const auto i = static_cast<std::size_t>(hi - cum.begin());
    const double len = cum[i] - cum[i - 1];
    return len > 0 ? Eigen::Vector3d(pts[i - 1] + (pts[i] - pts[i - 1]) * ((t - cum[i - 1]) / len)) : pts[i];
  };
  const Eigen::Vector3d up(0, 0, lift);
  Pass out;
  out.points.push_back(at(s0) + up);
  for (std::size_t i = 0; i < pts.size(); ++i)  // O(points)
    if (cum[i] > s0 && cum[i] < s1) out.points.push_back(pts[i] + up);
  out.points.push_back(at(s1) + up);
  return out;
}
}  // namespace

std::vector<Pass> stepped_runs(const Pass& piece, const std::function<Removal(double, double, double)>& removal,
                               double depth_mm, double min_cut_mm, double sample_mm, double run_on, double bridge,
                               int* raised, const OwnSweep& behind) {
  if (raised) *raised = 0;
  if (!removal || piece.points.size() < 2) return {piece};
  // The piece's cumulative length at its vertices, then densified (every sample_mm along its
  // segments) with the stock over each sample.
  std::vector<double> cum{0.0};
  for (std::size_t i = 1; i < piece.points.size(); ++i)  // O(points)
    cum.push_back(cum.back() + (piece.points[i] - piece.points[i - 1]).norm());
  std::vector<double> s, h, thick;      // path length, height and thickness the tool takes at the sample
  std::vector<Eigen::Vector3d> placed;  // the samples before (the piece's own sweep)
  for (std::size_t i = 0; i + 1 < piece.points.size(); ++i) {  // O(length / sample)
    const Eigen::Vector3d &a = piece.points[i], &b = piece.points[i + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / sample_mm)));
    for (int t = (i == 0 ? 0 : 1); t <= n; ++t) {
      const double f = static_cast<double>(t) / n;
      const Eigen::Vector3d p = a + (b - a) * f;
      s.push_back(cum[i] + (cum[i + 1] - cum[i]) * f);
      const Removal r = behind ? behind(p, placed.data(), placed.size()) : removal(p.x(), p.y(), p.z());
      h.push_back(r.height);
      thick.push_back(r.thickness);
      placed.push_back(p);
    }
  }
  const double most = *std::max_element(h.begin(), h.end());
  const int copies = depth_mm > 0 ? std::max(0, static_cast<int>(std::ceil(most / depth_mm)) - 1) : 0;
  std::vector<Pass> out;
  for (int k = copies; k >= 0; --k) {  // O(copies · samples)
    const double lift = k * depth_mm, over = lift + min_cut_mm;
    // Stretches where the tool cuts more than `over`, run on at both ends, merged where they meet:
    // a raised copy by the height it takes (the flutes), the piece itself by the thickness (the
    // scallop is measured normal to the surface).
    const std::vector<double>& take = k > 0 ? h : thick;
    std::vector<std::pair<double, double>> runs;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!(take[i] > over)) continue;
      std::size_t j = i;
      while (j + 1 < s.size() && take[j + 1] > over) ++j;
      const double a = std::max(0.0, s[i] - run_on), b = std::min(cum.back(), s[j] + run_on);
      if (!runs.empty() && a <= runs.back().second + bridge)
        runs.back().second = b;
      else
        runs.emplace_back(a, b);
      i = j;
    }
    if (k == 0 && runs.size() == 1 && runs.front().first <= 0 && runs.front().second >= cum.back()) {
      out.push_back(piece);  // the whole piece cuts: as planned (a loop stays a loop)
      continue;
    }
    if (raised && k > 0 && !runs.empty()) ++*raised;
    for (const auto& [a, b] : runs) out.push_back(stretch_of(piece.points, cum, a, b, lift));
  }
  return out;
}

Pass take_nearest(std::vector<Pass>& passes, std::vector<std::uint8_t>& done, const Eigen::Vector3d& at,
                  std::size_t* index) {
  std::size_t best = passes.size(), best_vertex = 0;
  bool reverse = false;
  double best_d = HUGE_VAL;
  for (std::size_t k = 0; k < passes.size(); ++k) {  // O(points) over the passes left
    if (done[k]) continue;
    const auto& pts = passes[k].points;
    if (best == passes.size()) best = k;
    if (passes[k].closed && pts.size() > 2 && (pts.front() - pts.back()).norm() < 1e-9) {
      // a loop may start at any of its vertices (its last repeats its first)
      for (std::size_t i = 0; i + 1 < pts.size(); ++i)
        if (const double d = (pts[i] - at).squaredNorm(); d < best_d)
          best_d = d, best = k, best_vertex = i, reverse = false;
      continue;
    }
    if (const double d = (pts.front() - at).squaredNorm(); d < best_d)
      best_d = d, best = k, best_vertex = 0, reverse = false;
    if (const double d = (pts.back() - at).squaredNorm(); d < best_d)
      best_d = d, best = k, best_vertex = 0, reverse = true;
  }
  done[best] = 1;
  if (index) *index = best;
  Pass p = std::move(passes[best]);
  if (reverse) std::reverse(p.points.begin(), p.points.end());
  if (p.closed && best_vertex > 0) {  // the loop's last point repeats its first
    p.points.pop_back();
    std::rotate(p.points.begin(), p.points.begin() + static_cast<std::ptrdiff_t>(best_vertex), p.points.end());
    p.points.push_back(p.points.front());
  }
  return p;
}

std::vector<Pass> order_nearest(std::vector<Pass> passes, Eigen::Vector3d& at, std::vector<std::size_t>* order) {
  std::vector<Pass> out;
  out.reserve(passes.size());
  std::vector<std::uint8_t> done(passes.size(), 0);
  std::vector<std::size_t> taken;                             // the order's entries, reordered
  for (std::size_t left = passes.size(); left > 0; --left) {  // O(passes²)
    std::size_t k = 0;
    out.push_back(take_nearest(passes, done, at, &k));
    if (order) taken.push_back((*order)[k]);
    at = out.back().points.back();
  }
  if (order) *order = std::move(taken);
  return out;
}

// Each piece where it cuts, from the top down, on a copy of the stock machined piece by piece:
// a piece cuts only where the tool takes more than the scallop off what the pieces before it
// left (a corner the pencil passes cleaned is not run over again: the air issue 41 names) — the
// most a cell stands above the tool's surface (RestStock::removal; not the axial engagement,
// which reads a cell grazed at the ball's rim as a cut as high as the cell stands), on the stock
// as the piece's own samples before leave it (removal_behind: a patch ends where the tool's front
// leaves it). No run-on: the last sample that takes more than the scallop is where the front
// leaves the patch, and before the first the tool took no more either (docs/finishing.md, "At
// the specification, by what it takes off": the air these took out). A piece that would take
// more than the flutes reach is preceded by raised copies of it, each begun from its end nearest
// the tool, a step apart: a copy takes at most a step, so the flutes meet at most a step plus
// what a copy leaves beside a wall (its profile's height at its rim: R for a ball) — the step is
// the flute length less that (s1 of README command 1, Ø1 ball with 1.5 mm flutes: 1 mm steps,
// the deepest cut 2.48 → 1.37 mm). No stepping under 0.1 mm steps (flutes shorter than the
// profile: the job's flute check says so). Without stated flutes the pieces are cut as planned:
// the z-map's columns would credit a pass's flank with a wall's whole rest above it, however tall.
// `depth` is that step (0: no stepping), `from` where the tool starts; pencil pieces first.
CutPieces cut_pieces(std::vector<Pass> pencil, std::vector<Pass> rest, const DropCutter& tool,
                     const RestRegions& regions, const FinishParams& params, double depth, Eigen::Vector3d from) {
  const tooling::Cutter& cutter = tool.cutter();
  // The stay-down link the linking would make from a to b (link_passes with a stock: along the drop
  // surface, never below the lower end, lifting where it would cut deeper than a step), cut into
  // the running stock: links take rest too (on s4 of README command 1, 924 of the 1,074 mm the
  // rest program's links fed cut), and a piece after one is judged on what it left — a piece
  // judged on the stock without them cut air where a link had gone first: s4's air 8.5 → 7.6 %,
  // its rest program 5.53 → 5.12 min. Predicted as a stay-down whenever the link is short
  // enough (the linking may still lift, by the machine's time): an upper bound of what it cuts.
  const double stay_max = params.tool.diameter * tol::stay_down_link_diameters + 4 * params.stepover_mm;
  const double h0 = std::min(tol::initial_sample_mm, cutter.radius() / 4);
  auto cut_link = [&](RestStock& st, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double d = (b.head<2>() - a.head<2>()).norm();
    if (d > stay_max || !(d > 0)) return;
    const double floor_z = std::min(a.z(), b.z());
    const int n = std::max(1, static_cast<int>(std::ceil(d / h0)));
    std::vector<Eigen::Vector3d> path{a};
    for (int i = 1; i < n; ++i) {  // O(d / h0) drops
      const Eigen::Vector2d q = a.head<2>() + (b.head<2>() - a.head<2>()) * (static_cast<double>(i) / n);
      const CLPoint c = tool.drop(q.x(), q.y());
      const double z = std::max(c.contact == Contact::None ? floor_z : c.z, floor_z);
      if (st.engagement(cutter, q.x(), q.y(), z) > depth) return;  // it would lift
      path.emplace_back(q.x(), q.y(), z);
    }
    path.push_back(b);
    cut_along(st, cutter, path);
  };
  std::optional<RestStock> running;
  if (depth > 0 && regions.left) running = *regions.left;
  // A stretch is left out where it would cut no more than the specification's scallop: it could
  // only smooth what is already in spec (leaving out stretches up to the rest threshold left 60 %
  // more rest over it on the pocket of CliJob's rest test).
  const double min_cut = std::clamp(params.scallop_mm, 0.0, regions.threshold_mm);
  CutPieces out;
  // The next piece is the one nearest where the tool is (not where the piece before ended: its
  // runs may end short of it, or it may cut nothing), the pencil pieces first.
  for (std::vector<Pass>* group : {&pencil, &rest}) {
    std::vector<std::uint8_t> done(group->size(), 0);
    for (std::size_t left = group->size(); left > 0; --left) {  // O(pieces · (points + samples · (R / cell)²))
      std::vector<Pass> runs{detail::take_nearest(*group, done, from)};
      // The link to the piece's start first, then the piece judged on what it leaves.
      const Eigen::Vector3d linked_to = runs.front().points.front();
      if (running && !out.passes.empty()) cut_link(*running, from, linked_to);
      if (running) {
        const Pass whole = std::move(runs.front());
        int raised = 0;
        runs = detail::stepped_runs(
            whole, [&](double x, double y, double z) { return running->removal(cutter, x, y, z); }, depth, min_cut,
            cutter.radius() / 4, 0.0, tol::rest_bridge_radii * cutter.radius(), &raised,
            [&](const Eigen::Vector3d& q, const Eigen::Vector3d* before, std::size_t n) {
              return running->removal_behind(cutter, q, before, n);
            });
        out.stepped += raised > 0 ? 1 : 0;
        out.air += runs.empty() ? 1 : 0;
      }
      for (Pass& c : runs) {
        if (!c.closed && (c.points.back() - from).squaredNorm() < (c.points.front() - from).squaredNorm())
          std::reverse(c.points.begin(), c.points.end());
        if (running && !out.passes.empty() && (c.points.front() - linked_to).norm() > 1e-9)
          cut_link(*running, from, c.points.front());  // a link cut above went elsewhere
        from = c.points.back();
        out.passes.push_back(std::move(c));
        if (running) cut_along(*running, cutter, out.passes.back().points);
      }
    }
  }
  return out;
}

}  // namespace detail

}  // namespace millnet::finish
