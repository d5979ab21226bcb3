// Work estimates of a pocket (work.hpp): tool-point grid, zigzag scan lines, feed-map cells.
#include "millnet/pocket/work.hpp"

#include "geometry_internal.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace millnet::pocket {

namespace {

detail::BBox boundary_box(const Region& region) {
  detail::BBox box;
  bool first = true;
  for (const Segment& s : segments(region.boundary)) {
    const detail::BBox b = detail::bbox(s);
    if (first) box = b;
    box.lo = box.lo.cwiseMin(b.lo);
    box.hi = box.hi.cwiseMax(b.hi);
    first = false;
  }
  return box;
}

std::string mm(double v) { return format_size(v); }

std::string over(const std::string& key, double value, const detail::BBox& box) {
  return key + " " + mm(value) + " mm over a " + mm(box.hi.x() - box.lo.x()) + " × " + mm(box.hi.y() - box.lo.y()) +
         " mm pocket";
}

}  // namespace

std::vector<WorkEstimate> estimate_work(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  std::vector<WorkEstimate> out;
  if (region.boundary.empty()) return out;
  cut.check("pocket");
  const detail::BBox box = boundary_box(region);
  if (const auto* som = std::get_if<SomSpec>(&spec)) {
    const double n = grid_range(region, som->frame).points();
    out.push_back({over("stepover", som->frame.spacing, box), n, "tool points", 24.0 * n});
    // The ring: M = max(3, round(node_factor · N)) nodes, N ≤ the grid points (som.hpp).
    const double m = std::max(3.0, std::round(som->som.node_factor * n));
    out.push_back({"node_factor " + mm(som->som.node_factor) + " × the tool points of " +
                       over("stepover", som->frame.spacing, box),
                   m, "SOM ring nodes", 32.0 * m});
  } else if (const auto* zz = std::get_if<ZigzagSpec>(&spec)) {
    const double diag = (box.hi - box.lo).norm();
    const double lines = std::floor(diag / cut.stepover) + 1;
    double directions = 1;
    if (!zz->zigzag.angle_deg) {
      const double step = zz->zigzag.angle_step_deg > 0 ? zz->zigzag.angle_step_deg : 1.0;
      directions = std::ceil(180.0 / step) + static_cast<double>(region.boundary.size());
    }
    const double n = lines * directions;
    out.push_back({over("stepover", cut.stepover, box), n, "zigzag scan lines", 64.0 * n});
  } else if (std::holds_alternative<OffsetSpec>(spec)) {
    // Offsets: at most half the box's smaller side / stepover + 1 of them, each as many vertices as
    // the walls flattened at the contour chord (round joins add about as many again): an upper bound
    // of the ring vertices, 16 bytes each.
    double verts = 0;
    verts += static_cast<double>(flatten(region.boundary, tol::contour_chord_mm).size());
    for (const Loop& isl : region.islands) verts += static_cast<double>(flatten(isl, tol::contour_chord_mm).size());
    const double k = std::floor(0.5 * std::min(box.hi.x() - box.lo.x(), box.hi.y() - box.lo.y()) / cut.stepover) + 1;
    const double n = 2 * verts * k;
    out.push_back({over("stepover", cut.stepover, box), n, "offset ring vertices", 16.0 * n});
  } else if (const auto* ad = std::get_if<AdaptiveSpec>(&spec)) {
    // The cleared-area raster over the box grown by D (a byte of state and of target, a double of
    // wall distance and an int of component per cell).
    const double h = adaptive_raster_mm(region, cut, ad->adaptive);
    const double n = std::ceil((box.hi.x() - box.lo.x() + 2 * cut.tool.diameter) / h) *
                     std::ceil((box.hi.y() - box.lo.y() + 2 * cut.tool.diameter) / h);
    out.push_back({over("raster_mm", h, box), n, "adaptive raster cells", 24.0 * n});
  }
  const double g = cut.feed_grid > 0 ? cut.feed_grid : cut.tool.diameter / 10;
  const double R = cut.tool.diameter / 2;
  const double nx = std::ceil((box.hi.x() - box.lo.x() + 2 * (R + g)) / g);
  const double ny = std::ceil((box.hi.y() - box.lo.y() + 2 * (R + g)) / g);
  out.push_back({over("feed_grid", g, box), nx * ny, "feed-map cells", nx * ny});
  return out;
}

void check_work(const Region& region, const CutParams& cut, const PlannerSpec& spec, const WorkLimits& limits) {
  for (const WorkEstimate& e : estimate_work(region, cut, spec)) millnet::check_work(e, limits);
}

}  // namespace millnet::pocket
