// The stock a simulation left, as rest.hpp reads it (RestStock), and the exact area a tool cannot
// reach (unreachable_regions: a point-like probe's rest behind it), and the rest program's passes
// cut to where they remove rest (detail::trim_to_rest).
#include "rest_internal.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/rest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace millnet::finish {
namespace {

void require_stock(bool ok, const std::string& key, const std::string& what) {
  if (!ok) throw Error("rest: " + key + " " + what);
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
  // Along the normal from p: how far until the point is above the stock (in the air)?
  auto in = [&](double t) { return height(p.x() + t * n.x(), p.y() + t * n.y()) - (p.z() + t * n.z()); };
  if (!(in(0) > 0)) return 0.0;
  const double cap = 64 * cell;
  double lo = 0, hi = cell / 4;
  while (in(hi) > 0) {  // O(log(cap / cell)) steps out
    if (hi >= cap) return cap;
    lo = hi;
    hi = std::min(2 * hi, cap);
  }
  for (int k = 0; k < 16; ++k) {  // bisection to (hi − lo) / 65536
    const double mid = 0.5 * (lo + hi);
    (in(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
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
  const DropCutter probe(mesh, tooling::Cutter::ball(0.01));
  return rest_regions(mesh, probe, rp);
}

namespace detail {

std::vector<Pass> trim_to_rest(const std::vector<Pass>& passes, const DropCutter& tool, const ingest::Mesh& mesh,
                               const RestRegions& regions) {
  if (!regions.material) return passes;
  const double eps = regions.threshold_mm / 4, run_on = tool.cutter().radius() / 4;
  std::vector<std::vector<Pass>> pieces(passes.size());
  const auto n = static_cast<std::ptrdiff_t>(passes.size());
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto& pts = passes[static_cast<std::size_t>(k)].points;
    const std::size_t m = pts.size();
    std::vector<double> s(m, 0.0);  // path length along the pass
    for (std::size_t i = 1; i < m; ++i) s[i] = s[i - 1] + (pts[i] - pts[i - 1]).norm();
    std::vector<std::uint8_t> cuts(m, 0), keep(m, 0);
    for (std::size_t i = 0; i < m; ++i) {  // O(points) drops
      const CLPoint c = tool.drop(pts[i].x(), pts[i].y());
      if (c.contact == Contact::None || c.triangle < 0) continue;
      cuts[i] = regions.material(c.cc, unit_normal(mesh, c.triangle)) > eps ? 1 : 0;
    }
    // Run on by the radius: forward then backward, from the last cutting point seen.
    double last = -HUGE_VAL;
    for (std::size_t i = 0; i < m; ++i) {
      if (cuts[i]) last = s[i];
      if (s[i] - last <= run_on) keep[i] = 1;
    }
    last = HUGE_VAL;
    for (std::size_t i = m; i-- > 0;) {
      if (cuts[i]) last = s[i];
      if (last - s[i] <= run_on) keep[i] = 1;
    }
    auto& mine = pieces[static_cast<std::size_t>(k)];
    Pass cur;
    for (std::size_t i = 0; i <= m; ++i) {
      if (i < m && keep[i]) {
        cur.points.push_back(pts[i]);
        continue;
      }
      if (cur.points.size() >= 2) mine.push_back(std::move(cur));
      cur = Pass{};
    }
    if (mine.size() == 1 && mine.front().points.size() == m)
      mine.front().closed = passes[static_cast<std::size_t>(k)].closed;
  }
  std::vector<Pass> out;
  for (auto& list : pieces)  // O(pieces), in pass order
    for (auto& piece : list) out.push_back(std::move(piece));
  return out;
}

}  // namespace detail

}  // namespace millnet::finish
