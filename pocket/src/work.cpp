// Work estimates of a pocket (work.hpp): the planner's (its registry entry's), then the feed map's.
#include "millnet/pocket/work.hpp"

#include "work_internal.hpp"
#include "millnet/core/atomic_file.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::pocket {

namespace detail {

BBox boundary_box(const Region& region) {
  BBox box;
  bool first = true;
  for (const Segment& s : segments(region.boundary)) {
    const BBox b = bbox(s);
    if (first) box = b;
    box.lo = box.lo.cwiseMin(b.lo);
    box.hi = box.hi.cwiseMax(b.hi);
    first = false;
  }
  return box;
}

std::string mm(double v) { return format_size(v); }

std::string over(const std::string& key, double value, const BBox& box) {
  return key + " " + mm(value) + " mm over a " + mm(box.hi.x() - box.lo.x()) + " × " + mm(box.hi.y() - box.lo.y()) +
         " mm pocket";
}

}  // namespace detail

std::vector<WorkEstimate> estimate_work(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  if (region.boundary.empty()) return {};
  cut.check("pocket");
  const detail::BBox box = detail::boundary_box(region);
  std::vector<WorkEstimate> out = spec.entry().estimate(region, cut, spec);
  const double g = cut.feed_grid > 0 ? cut.feed_grid : cut.tool.diameter / 10;
  const double R = cut.tool.diameter / 2;
  const double nx = std::ceil((box.hi.x() - box.lo.x() + 2 * (R + g)) / g);
  const double ny = std::ceil((box.hi.y() - box.lo.y() + 2 * (R + g)) / g);
  out.push_back({detail::over("feed_grid", g, box), nx * ny, "feed-map cells", nx * ny});
  return out;
}

void check_work(const Region& region, const CutParams& cut, const PlannerSpec& spec, const WorkLimits& limits) {
  for (const WorkEstimate& e : estimate_work(region, cut, spec)) millnet::check_work(e, limits);
}

}  // namespace millnet::pocket
