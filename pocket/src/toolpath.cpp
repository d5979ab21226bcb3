// Path2D figures and PlanStatus names.
#include "millnet/pocket/toolpath.hpp"

#include "millnet/core/error.hpp"

#include <cmath>
#include <string>

namespace millnet::pocket {

namespace {
double chain_length(const Chain& c) {
  double l = 0;
  for (std::size_t k = 0; k + 1 < c.pts.size(); ++k)
    l += length(Segment{c.pts[k].p(), c.pts[k + 1].p(), c.pts[k].bulge});
  return l;
}
}  // namespace

double Path2D::cut_length() const {
  double l = 0;
  for (const Chain& c : chains) l += chain_length(c);  // O(total vertices)
  return l;
}

double Path2D::rapid_length() const {
  double l = 0;
  for (std::size_t k = 0; k + 1 < chains.size(); ++k) {
    if (chains[k].pts.empty() || chains[k + 1].pts.empty()) continue;
    l += (chains[k + 1].pts.front().p() - chains[k].pts.back().p()).norm();
  }
  return l;
}

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::Ok: return "ok";
    case PlanStatus::NoToolPoints: return "no_tool_points";
    case PlanStatus::NothingToCut: return "nothing_to_cut";
  }
  return "unknown";
}

void CutParams::check(const std::string& who) const {
  const double tool_diameter = tool.diameter;
  if (!(tool_diameter > 0) || !std::isfinite(tool_diameter))
    throw Error(who + ": tool_diameter must be > 0 mm, got " + std::to_string(tool_diameter));
  if (!(stepover > 0) || stepover > tool_diameter)
    throw Error(who + ": stepover must be in (0, tool_diameter = " + std::to_string(tool_diameter) + "] mm, got " +
                std::to_string(stepover));
  if (!(stock_to_leave >= 0)) throw Error(who + ": stock_to_leave must be ≥ 0 mm");
}

}  // namespace millnet::pocket
