// Rest regions behind a reference tool and rest finishing inside them (rest.hpp): the new tool's
// contacts tested against the reference's placements, the regions cleaned, grown and traced, then
// strategy 1 inside their outline along the corners.
#include "millnet/finish/rest.hpp"

#include "boundary.hpp"
#include "rest_internal.hpp"
#include "contours.hpp"
#include "sampling.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>

namespace millnet::finish {
namespace {

using detail::Grid;

/// Node offsets within `radius` cells, nearest first (ties by offset: deterministic).
std::vector<std::pair<int, int>> disc_offsets(double radius_cells) {
  const int r = static_cast<int>(std::ceil(radius_cells));
  std::vector<std::pair<int, int>> out;
  for (int di = -r; di <= r; ++di)  // O(r²)
    for (int dj = -r; dj <= r; ++dj)
      if (di * di + dj * dj <= radius_cells * radius_cells) out.emplace_back(di, dj);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.first * a.first + a.second * a.second < b.first * b.first + b.second * b.second;
  });
  return out;
}

/// The material at p behind the reference: the nearest of its grid placements first (stopping at
/// the threshold), then, when that is above the threshold, a pattern search of real drops around
/// the best placement (steps halved down to cell/64), so that a placement between nodes (a wall
/// touched at an axis position off the grid) is found. `hint` (in and out; per row or triangle, so
/// the answers do not depend on the thread count): a placement that settles p at once when it is
/// within the threshold (the search never starts from it: it may lie in another basin), and the
/// best one found left there, so that neighbouring points settle with no drop where the reference
/// touched the surface between them.
double material_at(const Eigen::Vector3d& p, const Grid& g, const std::vector<double>& ref_cl, const DropCutter& ref,
                   const std::vector<std::pair<int, int>>& offsets, double thr, CLPoint& hint) {
  const tooling::Cutter& tool = ref.cutter();
  if (hint.contact != Contact::None && distance_to_tool(tool, hint.x, hint.y, hint.z, p) <= thr) return 0;
  const int bi = static_cast<int>(std::lround((p.y() - g.y0) / g.h));
  const int bj = static_cast<int>(std::lround((p.x() - g.x0) / g.h));
  double best = std::numeric_limits<double>::infinity();
  double bx = p.x(), by = p.y(), bz = 0;
  auto settle = [&](double value) {
    if (std::isfinite(best)) hint.x = bx, hint.y = by, hint.z = bz, hint.contact = Contact::Facet;
    return value;
  };
  for (const auto& [di, dj] : offsets) {  // O(offsets), usually a few
    const int i = bi + di, j = bj + dj;
    if (i < 0 || j < 0 || i >= g.ny || j >= g.nx) continue;
    const double tip = ref_cl[g.at(i, j)];
    if (!std::isfinite(tip)) continue;
    const double d = distance_to_tool(tool, g.x(j), g.y(i), tip, p);
    if (d < best) best = d, bx = g.x(j), by = g.y(i), bz = tip;
    if (best <= thr) return settle(0);
  }
  // The drops of the search so far, by position: a move's new neighbours include three of the
  // old centre's and the old centre itself (a drop is a function of its XY: the same answers).
  std::array<CLPoint, 32> seen;
  std::size_t n_seen = 0;
  auto drop = [&](double x, double y) {
    for (std::size_t k = 0; k < std::min(n_seen, seen.size()); ++k)  // O(32)
      if (seen[k].x == x && seen[k].y == y) return seen[k];
    CLPoint c = ref.drop(x, y);
    c.x = x, c.y = y;  // (the key: the drop's own position)
    seen[n_seen++ % seen.size()] = c;
    return c;
  };
  for (double s = g.h; s > g.h / 64; s *= 0.5) {  // O(log 64 · moves) drops
    bool moved = true;
    for (int guard = 0; moved && guard < 64; ++guard) {
      moved = false;
      for (const auto& [u, v] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}}) {
        const CLPoint c = drop(bx + s * u, by + s * v);
        if (c.contact == Contact::None) continue;
        const double d = distance_to_tool(tool, c.x, c.y, c.z, p);
        if (d < best) {
          best = d, bx = c.x, by = c.y, bz = c.z, moved = true;
          if (best <= thr) return settle(0);
        }
      }
    }
  }
  return settle(best);
}

/// Calls visit(q) at points of triangle f on a lattice of its two edges from vertex 0, each step at
/// most `spacing` (≤ 4096 per edge), vertices included. O(area / spacing²).
template <class Visit>
void sample_triangle(const ingest::Mesh& mesh, std::ptrdiff_t f, double spacing, Visit&& visit) {
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
  const int nu = std::clamp(static_cast<int>(std::ceil((b - a).norm() / spacing)), 1, 4096);
  const int nv = std::clamp(static_cast<int>(std::ceil((c - a).norm() / spacing)), 1, 4096);
  for (int u = 0; u <= nu; ++u)
    for (int v = 0; v * nu <= (nu - u) * nv; ++v)  // u/nu + v/nv ≤ 1
      visit(Eigen::Vector3d(a + (b - a) * (static_cast<double>(u) / nu) + (c - a) * (static_cast<double>(v) / nv)));
}

/// Rest from the stock, between the contacts: on a steep wall the new tool's contacts at
/// neighbouring nodes lie (step / cos slope) apart along the wall, too sparse for the scallops an
/// earlier tool left there. So the design itself is sampled (points on every upward triangle ≤
/// step/2 apart), and where the stock over a point exceeds the threshold the node under the axis of
/// the new tool touching it there (p + the tool's offset along the face's normal) is marked too.
/// Faces in parallel, each writing its own list: any thread count gives the same mask. O(design
/// area / (step/2)²).
void mark_stock_samples(const ingest::Mesh& mesh, const RestStock& stock, const tooling::Cutter& tool, double thr,
                        const Grid& g, RestRegions& out) {
  const double rc = tool.profile_corner_radius(), a = tool.radius() - rc;
  const auto faces = static_cast<std::ptrdiff_t>(mesh.F.rows());
  std::vector<std::vector<std::pair<std::size_t, float>>> marks(static_cast<std::size_t>(faces));
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t f = 0; f < faces; ++f) {
    const Eigen::Vector3d n = detail::unit_normal(mesh, f);
    if (n.z() < -1e-12) continue;  // facing down: no contact from above
    const double nxy = std::hypot(n.x(), n.y());
    const double scale = nxy > 1e-12 ? a / nxy + rc : 0.0;
    const Eigen::Vector2d off(n.x() * scale, n.y() * scale);
    auto& mine = marks[static_cast<std::size_t>(f)];
    sample_triangle(mesh, f, 0.5 * g.h, [&](const Eigen::Vector3d& q) {
      const double m = stock.material_over(q, n, thr);
      if (m <= thr) return;
      const int i = static_cast<int>(std::lround((q.y() + off.y() - g.y0) / g.h));
      const int j = static_cast<int>(std::lround((q.x() + off.x() - g.x0) / g.h));
      if (i >= 0 && j >= 0 && i < g.ny && j < g.nx) mine.emplace_back(g.at(i, j), static_cast<float>(m));
    });
  }
  for (const auto& list : marks)  // O(marks)
    for (const auto& [k, m] : list) {
      out.mask[k] = 1;
      if (!(out.thickness[k] >= m)) out.thickness[k] = m;  // (a NaN node: the tool touches nothing there)
    }
}

/// 4-connected components of `on` nodes: a component id per node (−1 off), in first-node order.
std::vector<int> components(const Grid& g, const std::vector<std::uint8_t>& on, int* count) {
  std::vector<int> id(g.size(), -1);
  std::vector<std::size_t> stack;
  int n = 0;
  for (std::size_t s = 0; s < g.size(); ++s) {  // O(nodes): each node pushed once
    if (!on[s] || id[s] >= 0) continue;
    id[s] = n;
    stack.push_back(s);
    while (!stack.empty()) {
      const std::size_t k = stack.back();
      stack.pop_back();
      const int i = static_cast<int>(k / static_cast<std::size_t>(g.nx)), j = static_cast<int>(k % g.nx);
      for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int a = i + di, b = j + dj;
        if (a < 0 || b < 0 || a >= g.ny || b >= g.nx) continue;
        const std::size_t q = g.at(a, b);
        if (on[q] && id[q] < 0) id[q] = n, stack.push_back(q);
      }
    }
    ++n;
  }
  *count = n;
  return id;
}

void require_rest(bool ok, const std::string& key, const std::string& what) {
  if (!ok) throw Error("rest: " + key + " " + what);
}

}  // namespace

namespace detail {

/// Sampled passes (steps ≤ 0.25 mm) cut to the machining boundary (pieces shorter than
/// tol::min_pass_mm dropped), then simplified to the chord tolerance.
std::vector<Pass> clip_passes(const detail::Fence& fence, const std::vector<Pass>& passes, double chord_tolerance_mm) {
  std::vector<Pass> out;
  for (const Pass& p : passes) {  // O(points · log(step / tol))
    std::vector<std::vector<detail::Sample>> one(1);
    for (const auto& q : p.points) one.front().push_back({q, 0});
    for (auto& piece : fence.clip(std::move(one))) {
      Pass kept;
      for (const auto& q : detail::simplify(piece, chord_tolerance_mm, false)) kept.points.push_back(q.p);
      out.push_back(std::move(kept));
    }
  }
  return out;
}

/// A rest region's passes (p.boundary: its outline and Z range): the steep pieces of the Z-levels,
/// top-down, then the shallow runs of loops a constant 3D distance p_f apart inside its outline
/// (strategy 5's fast marching started from the outline), which run along the corner whatever its
/// shape (a ring around a cavity's floor too), cut to the boundary and simplified. A region
/// narrower than the tool is traced in a box as wide as the tool.
std::vector<Pass> corner_passes(const ingest::Mesh& mesh, const DropCutter& tool, const FinishParams& p) {
  detail::Box box{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& poly : p.boundary.polygons)  // O(polygon points)
    for (const Eigen::Vector2d& q : poly)
      box = {std::min(box.x0, q.x()), std::min(box.y0, q.y()), std::max(box.x1, q.x()), std::max(box.y1, q.y())};
  if (!(box.x1 >= box.x0 && box.y1 >= box.y0)) return {};
  // A region narrower than the tool (a band of axis positions along a wall, where the tool sweeps a
  // band of design a diameter wider) is traced in a box widened to the diameter; the fence keeps its
  // passes inside the outline.
  const double wx = std::max(0.0, p.tool.diameter - (box.x1 - box.x0)) / 2,
               wy = std::max(0.0, p.tool.diameter - (box.y1 - box.y0)) / 2;
  box = {box.x0 - wx, box.y0 - wy, box.x1 + wx, box.y1 + wy};
  const detail::Sampler s(mesh, tool);
  const detail::Fence fence(mesh, p.boundary);
  const double shallow_to = p.boundary_angle_deg + tol::slope_overlap_deg;
  std::vector<std::vector<detail::Sample>> lines =
      detail::order_by_level(detail::steep_pieces(detail::waterline_loops(s, box, p, true), p), p.tool.diameter);
  for (const auto& level : detail::equidistant_loops(s, box, p, true))
    for (const auto& loop : level)
      for (auto& r : detail::runs(loop, [&](const detail::Sample& q) { return q.slope_deg < shallow_to; }))
        lines.push_back(std::move(r));
  lines = fence.clip(std::move(lines));
  for (auto& line : lines) line = detail::simplify(line, p.chord_tolerance_mm, false);
  return detail::to_passes(std::move(lines));
}

/// The plan's program made again from its passes (pencil passes put in front).
void relink(const ingest::Mesh& mesh, const DropCutter& tool, const FinishParams& p, FinishPlan& plan) {
  plan.program = {};
  plan.path_length_mm = 0, plan.lifts = 0, plan.hops = 0, plan.cl_points = 0;
  const detail::Sampler s(mesh, tool);
  const detail::Fence fence(mesh, p.boundary);
  detail::link_passes(s, p, fence, plan);
}

}  // namespace detail

void RestParams::check() const {
  check_finishing_cutter(reference);
  require_rest(std::isfinite(threshold_mm) && threshold_mm > 0, "threshold_mm",
               "must be > 0 (got " + std::to_string(threshold_mm) + ")");
  require_rest(std::isfinite(margin_mm) && margin_mm <= 100, "margin_mm", "must be ≤ 100 (< 0: automatic)");
  require_rest(std::isfinite(min_area_mm2), "min_area_mm2", "must be finite (< 0: automatic)");
  require_rest(std::isfinite(cell_mm) && (cell_mm == 0 || (cell_mm >= 0.005 && cell_mm <= 5)), "cell_mm",
               "must be 0 (automatic) or in [0.005, 5] mm (got " + std::to_string(cell_mm) + ")");
}

double rest_cell_mm(const tooling::Cutter& reference, double threshold_mm) {
  const double t = threshold_mm / 4, rc = reference.profile_corner_radius(), a = reference.radius() - rc;
  const double d = rc > 0 ? a + std::sqrt(std::max(0.0, 2 * rc * t - t * t)) : reference.radius();
  return std::clamp(d * std::numbers::sqrt2, 0.02, 0.25);
}

double distance_to_tool(const tooling::Cutter& tool, double cx, double cy, double tip, const Eigen::Vector3d& p) {
  return tool.distance_to_solid(cx, cy, tip, p.x(), p.y(), p.z());
}

RestRegions rest_regions(const ingest::Mesh& mesh, const DropCutter& new_tool, const RestParams& params, double x0,
                         double y0, double x1, double y1) {
  params.check();
  const tooling::Cutter& tool = new_tool.cutter();
  if (params.stock != nullptr) params.stock->check();
  if (params.stock == nullptr && params.reference.radius() < tool.radius())
    throw Error("rest: the reference tool (" + params.reference.describe() + ") is smaller than the rest tool (" +
                tool.describe() + "): it leaves nothing the rest tool can take");
  if (!(x1 > x0 && y1 > y0))
    x0 = mesh.V.col(0).minCoeff(), y0 = mesh.V.col(1).minCoeff(), x1 = mesh.V.col(0).maxCoeff(),
    y1 = mesh.V.col(1).maxCoeff();
  // From the stock: the new tool's own step (its contacts as dense as a reference of its size needs),
  // not finer than the stock's cells.
  const double h = params.cell_mm > 0 ? params.cell_mm
                   : params.stock     ? std::max(params.stock->cell, rest_cell_mm(tool, params.threshold_mm))
                                      : rest_cell_mm(params.reference, params.threshold_mm);
  const double cells = std::ceil((x1 - x0) / h + 1) * std::ceil((y1 - y0) / h + 1);
  if (!(cells <= 5e7))
    throw Error("rest: a grid of " + std::to_string(static_cast<long long>(cells)) + " nodes at " + std::to_string(h) +
                " mm exceeds the limit of 50,000,000 (raise cell_mm or the threshold)");
  const Grid g{x0, y0, h, static_cast<int>(std::ceil((x1 - x0) / h - 1e-9)) + 1,
               static_cast<int>(std::ceil((y1 - y0) / h - 1e-9)) + 1};
  RestRegions out;
  out.x0 = g.x0, out.y0 = g.y0, out.cell = h, out.nx = g.nx, out.ny = g.ny;
  out.threshold_mm = params.threshold_mm;

  // 1. The new tool's contacts and the reference's placements on the same nodes.
  std::vector<Eigen::Vector2d> xy(g.size());
  for (int i = 0; i < g.ny; ++i)  // O(nodes)
    for (int j = 0; j < g.nx; ++j) xy[g.at(i, j)] = {g.x(j), g.y(i)};
  const std::vector<CLPoint> cl = new_tool.drop(xy);
  // The reference's placements, kept with the material model handed on to plan_rest.
  struct Reference {
    DropCutter tool;
    std::vector<double> cl;
    std::vector<std::pair<int, int>> offsets;
  };
  std::shared_ptr<const Reference> ref;
  if (params.stock == nullptr) {
    DropCutter rt(mesh, params.reference);
    std::vector<double> rcl = rt.drop_grid(g.x0, g.y0, h, g.nx, g.ny);
    ref = std::make_shared<const Reference>(Reference{
        std::move(rt), std::move(rcl), disc_offsets((params.reference.radius() + params.threshold_mm) / h + 1)});
  }
  // The material at a design point with normal n: behind the reference's placements, or under the
  // stock (along n).
  const RestStock* stock = params.stock;
  const double thr = params.threshold_mm;
  // (`floor`: only whether it exceeds that is asked; RestStock::material_over)
  auto material = [stock, ref, g, thr](const Eigen::Vector3d& p, const Eigen::Vector3d& n, CLPoint& hint,
                                       double floor = -std::numeric_limits<double>::infinity()) {
    return stock ? stock->material_over(p, n, floor) : material_at(p, g, ref->cl, ref->tool, ref->offsets, thr, hint);
  };
  out.material = [material](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    CLPoint hint;
    return material(p, n, hint);
  };
  auto face_normal = [&](std::ptrdiff_t f) { return detail::unit_normal(mesh, f); };

  // 2. The material at each contact (rows in parallel; each node on its own: any thread count).
  out.thickness.assign(g.size(), 0.0F);
  out.mask.assign(g.size(), 0);
#pragma omp parallel for schedule(dynamic, 8)
  for (int i = 0; i < g.ny; ++i) {
    CLPoint hint;  // the row's last placement
    for (int j = 0; j < g.nx; ++j) {
      const std::size_t k = g.at(i, j);
      if (cl[k].contact == Contact::None) {
        out.thickness[k] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      const double m = material(cl[k].cc, face_normal(cl[k].triangle), hint);
      out.thickness[k] = static_cast<float>(m);
      out.mask[k] = m > params.threshold_mm ? 1 : 0;
    }
  }
  if (params.stock) mark_stock_samples(mesh, *params.stock, tool, params.threshold_mm, g, out);

  // 3. Slivers dropped: components whose axis area is below the minimum.
  const double min_area =
      params.min_area_mm2 >= 0 ? params.min_area_mm2 : std::numbers::pi * tool.radius() * tool.radius() / 4;
  int n = 0;
  const std::vector<int> id = components(g, out.mask, &n);
  std::vector<double> area(static_cast<std::size_t>(n), 0.0), sx(area), sy(area), sxx(area), syy(area), sxy(area);
  for (std::size_t k = 0; k < g.size(); ++k) {  // O(nodes)
    if (id[k] < 0) continue;
    const auto c = static_cast<std::size_t>(id[k]);
    const double x = g.x(static_cast<int>(k % g.nx)), y = g.y(static_cast<int>(k / g.nx));
    area[c] += h * h, sx[c] += x, sy[c] += y, sxx[c] += x * x, syy[c] += y * y, sxy[c] += x * y;
  }
  std::vector<std::uint8_t> kept(g.size(), 0);
  double cxx = 0, cyy = 0, cxy = 0;  // the kept regions' second moments about their own centroids
  for (std::size_t c = 0; c < area.size(); ++c) {
    if (area[c] < min_area) {
      ++out.slivers;
      continue;
    }
    ++out.regions;
    out.rest_axis_area_mm2 += area[c];
    const double m = area[c] / (h * h), mx = sx[c] / m, my = sy[c] / m;
    cxx += sxx[c] - m * mx * mx, cyy += syy[c] - m * my * my, cxy += sxy[c] - m * mx * my;
  }
  for (std::size_t k = 0; k < g.size(); ++k)
    if (id[k] >= 0 && area[static_cast<std::size_t>(id[k])] >= min_area) {
      kept[k] = 1;
      out.max_thickness_mm = std::max(out.max_thickness_mm, static_cast<double>(out.thickness[k]));
    }
  double axis = 0.5 * std::atan2(2 * cxy, cxx - cyy) * 180 / std::numbers::pi;
  if (axis < 0) axis += 180;
  out.axis_deg = axis;

  // 4. Grown by the margin (a disc of nodes around each kept node).
  const double margin = params.margin_mm >= 0 ? params.margin_mm : tool.radius() / 2;
  const auto grow = disc_offsets(margin / h);
  std::vector<std::uint8_t> grown(g.size(), 0);
  for (int i = 0; i < g.ny; ++i)  // O(kept nodes · (margin / h)²)
    for (int j = 0; j < g.nx; ++j) {
      if (!kept[g.at(i, j)]) continue;
      for (const auto& [di, dj] : grow) {
        const int a = i + di, b = j + dj;
        if (a >= 0 && b >= 0 && a < g.ny && b < g.nx) grown[g.at(a, b)] = 1;
      }
    }
  for (std::size_t k = 0; k < g.size(); ++k)
    if (grown[k]) out.mask[k] = 2;
  if (stock) {  // what the links and entries clear
    out.stock_tip = [stock, tool](double x, double y) { return stock->clearing_tip(tool, x, y); };
    out.left = std::shared_ptr<const RestStock>(std::shared_ptr<const RestStock>(), stock);  // not owned
    out.from_stock = true;
  } else {
    // The reference's envelope near the regions (+ the threshold for its cusps); elsewhere the new
    // tool on the reference's tip, raised until its profile clears the reference's.
    auto env = std::make_shared<const RestStock>(detail::reference_envelope(
        params.reference, ref->cl, g.x0, g.y0, h, g.nx, g.ny, grown, tool.radius() + 2 * h, thr));
    double rise = 0;
    for (int k = 0; k <= 64; ++k)  // O(1) samples of the new tool's radius
      rise = std::max(
          rise, params.reference.profile_height(tool.radius() * k / 64) - tool.profile_height(tool.radius() * k / 64));
    out.left = env;
    out.stock_tip = [ref, env, tool, lift = rise + thr](double x, double y) {
      const double tip = env->clearing_tip(tool, x, y);
      return tip < HUGE_VAL ? tip : ref->tool.drop(x, y).z + lift;
    };
  }

  // 5. The grown regions (4-connected components of the grown nodes: margins may join kept ones),
  // each with its outline, its Z range and its direction.
  int ng = 0;
  const std::vector<int> gid = components(g, grown, &ng);
  out.parts.resize(static_cast<std::size_t>(ng));
  std::vector<double> pxx(out.parts.size(), 0.0), pyy(pxx), pxy(pxx), pm(pxx), psx(pxx), psy(pxx);
  std::vector<std::array<int, 4>> bbox(out.parts.size(), {g.ny, g.nx, -1, -1});
  for (int i = 0; i < g.ny; ++i)  // O(nodes)
    for (int j = 0; j < g.nx; ++j) {
      const std::size_t k = g.at(i, j);
      if (gid[k] < 0) continue;
      const auto c = static_cast<std::size_t>(gid[k]);
      auto& bb = bbox[c];
      bb = {std::min(bb[0], i), std::min(bb[1], j), std::max(bb[2], i), std::max(bb[3], j)};
      RestRegion& part = out.parts[c];
      part.z_min = std::min(part.z_min, cl[k].contact == Contact::None ? part.z_min : cl[k].z);
      if (!kept[k]) continue;
      part.rest_axis_area_mm2 += h * h;
      const double x = g.x(j), y = g.y(i);
      pm[c] += 1, psx[c] += x, psy[c] += y, pxx[c] += x * x, pyy[c] += y * y, pxy[c] += x * y;
    }
  for (std::size_t c = 0; c < out.parts.size(); ++c) {
    const double m = std::max(pm[c], 1.0), mx = psx[c] / m, my = psy[c] / m;
    double a = 0.5 * std::atan2(2 * (pxy[c] - m * mx * my), (pxx[c] - m * mx * mx) - (pyy[c] - m * my * my)) * 180 /
               std::numbers::pi;
    out.parts[c].axis_deg = a < 0 ? a + 180 : a;
  }

  if (params.mask_only) return out;

  // 6. Each region's ceiling: the highest design point within the new tool's reach of it whose
  // material behind the reference exceeds the threshold (points on every triangle there, ≤ cell/2
  // apart, each tested like a contact above). A tip above the highest rest cuts none of it: Z-levels
  // up a wall the reference touched are left out. A point belongs to the region of the nearest
  // grown node within reach.
  const auto reach = disc_offsets(tool.radius() / h + 1);
  auto nearest_region = [&](int bi, int bj) {
    for (const auto& [di, dj] : reach) {  // O(reach), nearest first
      const int i = bi + di, j = bj + dj;
      if (i >= 0 && j >= 0 && i < g.ny && j < g.nx && gid[g.at(i, j)] >= 0) return gid[g.at(i, j)];
    }
    return -1;
  };
  // The answer depends on the node a point rounds to only: found once per node (rows in parallel),
  // not once per sample (points off the grid search on their own).
  std::vector<int> near_region(g.size(), -1);
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < g.ny; ++i)  // O(nodes · reach)
    for (int j = 0; j < g.nx; ++j) near_region[g.at(i, j)] = nearest_region(i, j);
  auto region_of = [&](const Eigen::Vector3d& q) {
    const auto bi = static_cast<int>(std::lround((q.y() - g.y0) / h)),
               bj = static_cast<int>(std::lround((q.x() - g.x0) / h));
    if (bi >= 0 && bj >= 0 && bi < g.ny && bj < g.nx) return near_region[g.at(bi, bj)];
    return nearest_region(bi, bj);
  };
  const auto faces = static_cast<std::ptrdiff_t>(mesh.F.rows());
  std::vector<std::vector<double>> tops(static_cast<std::size_t>(faces));
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t f = 0; f < faces; ++f) {  // O(sampled area / (h/2)²) over the near faces
    const Eigen::Vector3d nf = face_normal(f);
    std::vector<double> mine;
    CLPoint hint;  // the triangle's last placement
    sample_triangle(mesh, f, 0.5 * h, [&](const Eigen::Vector3d& q) {
      const int r = region_of(q);
      if (r < 0) return;
      if (mine.empty()) mine.assign(out.parts.size(), -std::numeric_limits<double>::infinity());
      if (q.z() <= mine[static_cast<std::size_t>(r)]) return;
      if (material(q, nf, hint, params.threshold_mm) > params.threshold_mm) mine[static_cast<std::size_t>(r)] = q.z();
    });
    tops[static_cast<std::size_t>(f)] = std::move(mine);
  }
  for (const auto& t : tops)  // O(faces · regions) where sampled
    for (std::size_t c = 0; c < t.size(); ++c) out.parts[c].z_max = std::max(out.parts[c].z_max, t[c]);
  for (const RestRegion& part : out.parts) out.rest_top_z = std::max(out.rest_top_z, part.z_max);
  if (std::isfinite(out.rest_top_z)) out.boundary.z_max = out.rest_top_z;

  // 7. The outlines: marching squares on each region's nodes (its box and a ring), crossings
  // halfway between nodes; the union's outlines for the whole.
  const detail::PlaceCrossing half = [](const Eigen::Vector2d& in, const Eigen::Vector2d& outside, double, double,
                                        bool) {
    return std::pair{Eigen::Vector2d(0.5 * (in + outside)), 0.0};
  };
  auto trace = [&](int i0, int j0, int i1, int j1, auto&& on) {
    detail::GridSpec gs;
    gs.x0 = g.x(j0), gs.y0 = g.y(i0), gs.step = h, gs.nx = j1 - j0 + 1, gs.ny = i1 - i0 + 1;
    gs.x1 = g.x(j1), gs.y1 = g.y(i1);
    std::vector<double> field(static_cast<std::size_t>(gs.nx) * static_cast<std::size_t>(gs.ny));
    for (int i = i0; i <= i1; ++i)  // O(box nodes)
      for (int j = j0; j <= j1; ++j)
        field[static_cast<std::size_t>(i - i0) * static_cast<std::size_t>(gs.nx) + static_cast<std::size_t>(j - j0)] =
            on(g.at(i, j)) ? 1.0 : 0.0;
    std::vector<std::vector<Eigen::Vector2d>> polys;
    for (const auto& loop : detail::iso_contours(gs, field, 0.5, half)) {
      std::vector<Eigen::Vector2d> poly;
      for (std::size_t q = 0; q + 1 < loop.size(); ++q) poly.push_back(loop[q].xy);  // last = first
      if (poly.size() >= 3) polys.push_back(std::move(poly));
    }
    return polys;
  };
  for (std::size_t c = 0; c < out.parts.size(); ++c) {
    const auto& bb = bbox[c];
    out.parts[c].boundary.polygons =
        trace(bb[0], bb[1], bb[2], bb[3], [&](std::size_t k) { return gid[k] == static_cast<int>(c); });
    out.parts[c].boundary.z_min = out.parts[c].z_min;
    out.parts[c].boundary.z_max = out.parts[c].z_max;
  }
  if (ng > 0) out.boundary.polygons = trace(0, 0, g.ny - 1, g.nx - 1, [&](std::size_t k) { return grown[k] != 0; });
  return out;
}

RestAgainstFloor against_floor(const RestRegions& regions, double floor_z) {
  RestAgainstFloor out;
  for (const RestRegion& g : regions.parts) {  // O(regions)
    if (g.z_min < floor_z) ++out.deeper, out.lowest_z = std::min(out.lowest_z, g.z_min);
    if (g.z_max > floor_z) ++out.within;
  }
  return out;
}

FinishPlan plan_rest(const ingest::Mesh& mesh, const DropCutter& new_tool, const RestRegions& regions,
                     const std::string& behind, FinishParams params) {
  if (regions.empty())
    throw Error("rest: no rest material behind " + behind + " for " + params.tool.describe() + " (nothing to finish)");
  // Each region on its own: its outline, its Z range (within the caller's), its direction.
  FinishPlan plan;
  plan.strategy = Strategy::SlopeMode;
  std::vector<Pass> corner;
  std::vector<std::size_t> region_of;                       // per corner pass
  for (std::size_t c = 0; c < regions.parts.size(); ++c) {  // O(regions) plans
    const RestRegion& region = regions.parts[c];
    if (!std::isfinite(region.z_max)) continue;  // no rest within reach above the threshold
    FinishParams p = params;
    p.boundary.polygons = region.boundary.polygons;
    p.boundary.z_min = std::max(params.boundary.z_min, region.boundary.z_min - params.step_down_mm);
    p.boundary.z_max = std::min(params.boundary.z_max, region.boundary.z_max);
    if (!(p.boundary.z_min < p.boundary.z_max)) continue;  // wholly outside the caller's Z range
    p.raster_angle_deg = region.axis_deg;
    for (Pass& pass : detail::corner_passes(mesh, new_tool, p)) {
      corner.push_back(std::move(pass));
      region_of.push_back(c);
    }
  }
  // The corners themselves first: pencil passes within the regions (their grid and mask), below
  // the rest's top.
  params.boundary.polygons = regions.boundary.polygons;
  params.boundary.z_max = std::min(params.boundary.z_max, regions.boundary.z_max);
  std::vector<std::uint8_t> inside(regions.mask.size());
  for (std::size_t k = 0; k < inside.size(); ++k) inside[k] = regions.mask[k] == 2 ? 1 : 0;
  const double x1 = regions.x0 + regions.cell * (regions.nx - 1), y1 = regions.y0 + regions.cell * (regions.ny - 1);
  // In machining order (nearest first: the pencil passes, then the regions' passes from where the
  // pencil ended), each pass cut to where it removes rest that the ones before it left.
  Eigen::Vector3d at(regions.x0, regions.y0, params.safe_z_mm - params.z_shift);
  std::vector<Pass> passes =
      detail::order_nearest(detail::clip_passes(detail::Fence(mesh, params.boundary),
                                                pencil_passes(mesh, new_tool, regions.x0, regions.y0, x1, y1,
                                                              regions.cell, params.chord_tolerance_mm, &inside),
                                                params.chord_tolerance_mm),
                            at);
  const std::size_t pencils = passes.size();
  std::vector<std::size_t> order(corner.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<Pass> corner_ordered = detail::order_nearest(corner, at, &order);
  passes.insert(passes.end(), std::make_move_iterator(corner_ordered.begin()),
                std::make_move_iterator(corner_ordered.end()));
  std::optional<detail::RestPoints> left;
  const std::vector<std::vector<Pass>> pieces = detail::trim_to_rest(passes, new_tool, mesh, regions, &left);
  // Then passes aimed at the rest they left where the tool reaches it, within the fence.
  // A placement reaching one point is kept where the stock's rest was measured by the programs
  // that left it: each point is then one the rest program's result is judged by.
  const std::size_t min_points =
      regions.left && !regions.left->exact_mm.empty() ? tol::rest_aim_min_points_measured : tol::rest_aim_min_points;
  std::vector<Pass> aimed;
  if (left) {
    const detail::Fence fence(mesh, params.boundary);
    aimed = detail::clip_passes(
        fence,
        detail::aim_at_rest(
            mesh, new_tool, *left, params.chord_tolerance_mm,
            [&fence](const Eigen::Vector3d& p) { return fence.inside(p); }, params.boundary.z_min, min_points),
        params.chord_tolerance_mm);
  }
  // The pieces nearest first again (pencil pieces first); regions left with pencil passes only.
  std::vector<Pass> pencil, rest;
  std::vector<std::uint8_t> cut(regions.parts.size(), 0);
  for (std::size_t k = 0; k < pieces.size(); ++k) {  // O(pieces)
    if (k >= pencils && !pieces[k].empty()) cut[region_of[order[k - pencils]]] = 1;
    for (const Pass& piece : pieces[k]) (k < pencils ? pencil : rest).push_back(piece);
  }
  const std::size_t aimed_passes = aimed.size();
  rest.insert(rest.end(), std::make_move_iterator(aimed.begin()), std::make_move_iterator(aimed.end()));
  const auto narrow = static_cast<std::size_t>(std::count(cut.begin(), cut.end(), 0));
  const Eigen::Vector3d start(regions.x0, regions.y0, params.safe_z_mm - params.z_shift);
  const tooling::Cutter& cutter = new_tool.cutter();
  // A tenth of the flutes kept in reserve for what stands between the stepping's samples and the
  // stock's columns (s1's job: 1.54 mm met with 1.5 mm flutes and none kept).
  const double step = 0.9 * params.tool.flute_length_mm - cutter.profile_height(cutter.radius());
  const double depth = step >= 0.1 ? step : 0.0;
  const std::size_t pencil_pieces = pencil.size();
  detail::CutPieces cut_out =
      detail::cut_pieces(std::move(pencil), std::move(rest), new_tool, regions, params, depth, start);
  plan.passes = std::move(cut_out.passes);
  params.stock_tip = regions.stock_tip;
  if (depth > 0 && regions.left) {  // the links judged on the stock as the program leaves it
    auto linked = std::make_shared<RestStock>(*regions.left);
    params.stock_engagement = [linked, cutter](double x, double y, double z) {
      return linked->engagement(cutter, x, y, z);
    };
    params.stock_cut = [linked, cutter](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      linked->cut(cutter, a, b);
    };
    params.stock_cut_depth = [linked, cutter](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return linked->cut_depth(cutter, a, b);
    };
    params.link_max_cut_mm = depth;
  }
  if (plan.passes.empty())
    throw NoRestToCut("rest: in the rest regions behind " + behind + " no pass of " + params.tool.describe() +
                      " removes rest and no concave edge is there to trace");
  params.comments.insert(
      params.comments.begin(),
      "rest finishing behind " + behind + ": " + std::to_string(regions.parts.size()) + " region(s) (" +
          std::to_string(narrow) + " pencil only), " + std::to_string(pencil_pieces) + " pencil pass(es) first" +
          (aimed_passes > 0 ? ", " + std::to_string(aimed_passes) + " aimed at rest the passes left" : std::string()) +
          (cut_out.stepped > 0 ? ", " + std::to_string(cut_out.stepped) + " piece(s) stepped down from the top"
                               : std::string()) +
          (cut_out.air > 0 ? ", " + std::to_string(cut_out.air) + " left out where the pieces before had cut"
                           : std::string()));
  detail::relink(mesh, new_tool, params, plan);
  return plan;
}

}  // namespace millnet::finish
