// Work estimates of the finishing strategies (work.hpp): raster drop-cutter grids, waterline CL
// grids, equidistant fast-marching grids.
#include "millnet/finish/work.hpp"

#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::finish {

namespace {
std::string over(const char* key, double v, double w, double h) {
  return std::string(key) + " " + format_size(v) + " mm over a " + format_size(w) + " × " + format_size(h) +
         " mm machining boundary";
}
double grid_points(double w, double h, double g) {
  return (std::ceil(w / g - 1e-9) + 1) * (std::ceil(h / g - 1e-9) + 1);
}
}  // namespace

std::vector<WorkEstimate> estimate_work(double x0, double y0, double x1, double y1,
                                        const std::vector<Strategy>& strategies, const FinishParams& p) {
  p.check();
  const double w = x1 - x0, h = y1 - y0, R = p.tool.radius();
  unsigned sampling = 0;  // the grids of every strategy asked, each counted once (the registry says which)
  for (const Strategy s : strategies)
    for (const StrategyInfo& e : strategy_registry())
      if (e.id == s) sampling |= e.sampling;
  const bool raster = sampling & kRasterSampling, waterline = sampling & kWaterlineSampling,
             equidistant = sampling & kEquidistantSampling, scallop = sampling & kScallopSampling;
  std::vector<WorkEstimate> out;
  // Raster passes `spacing` apart across the rotated box, sampled every h0 along.
  const double a = p.raster_angle_deg * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  const double along = w * c + h * s, across = w * s + h * c;  // the rotated box's sides
  const double h0 = std::min(tol::initial_sample_mm, R / 4);
  auto raster_points = [&](double spacing) {
    return (std::ceil(across / spacing - 1e-9) + 1) * (std::ceil(along / h0 - 1e-9) + 1);
  };
  if (raster) {
    const double n = raster_points(p.stepover_mm);
    out.push_back({over("stepover", p.stepover_mm, w, h), n, "raster CL points", 24.0 * n});
  }
  if (scallop) {
    // Issue 42 §7: scallop 1e-9 spaced the passes 1e-4 mm apart, unestimated (a hang). The passes
    // start at the scallop's spacing (flat faces keep it, steep ones close in to stepover × 0.1).
    const double spacing = detail::scallop_spacing(p.tool, p.scallop_mm);
    const double n = raster_points(spacing);
    out.push_back({"scallop " + format_size(p.scallop_mm) + " mm (passes " + format_size(spacing) +
                       " mm apart) over a " + format_size(w) + " × " + format_size(h) + " mm machining boundary",
                   n, "scallop-mode CL points", 24.0 * n});
  }
  if (waterline) {
    const double g = std::min(tol::waterline_grid_mm, R / 2);
    const double n = grid_points(w, h, g);
    out.push_back({over("tool radius", R, w, h), n, "waterline CL grid points", 24.0 * n});
  }
  if (equidistant) {
    const double g = std::min(tol::equidistant_grid_mm, p.stepover_mm / 2);
    const double n = grid_points(w, h, g);
    out.push_back({over("stepover", p.stepover_mm, w, h), n, "equidistant grid points", 24.0 * n});
  }
  return out;
}

}  // namespace millnet::finish
