#pragma once
// What the finishing strategies will cost over a machining box, before any CL point is dropped
// (issue 12 §1; core/budget.hpp). Per strategy, 24 bytes (a 3D point) per item:
//  * 1, 2 (raster passes): passes (⌈height across / stepover⌉ + 1) × first samples per pass
//    (⌈length along / h0⌉ + 1), h0 = min(tol::initial_sample_mm, R/4), along the raster angle's
//    frame — the drop-cutter grid before adaptive halving;
//  * 3 (scallop mode): the same grid with the passes at the scallop height's spacing
//    (detail::scallop_spacing, where its passes start; flat faces keep it);
//  * 1, 4 (waterline): the CL height grid that seeds the contours, g = min(tol::waterline_grid_mm, R/2),
//    (⌈W/g⌉ + 1)(⌈H/g⌉ + 1) (its Z levels are bounded by tol::max_waterline_levels);
//  * 5 (equidistant): the fast-marching grid, g = min(tol::equidistant_grid_mm, p_f/2), same count.
#include "millnet/core/budget.hpp"
#include "millnet/finish/strategy.hpp"

#include <vector>

namespace millnet::finish {

/// Estimates of `strategies` over the XY box [x0, x1] × [y0, y1] (mesh frame, mm) with `params`
/// (checked); one per distinct grid (a raster or waterline grid shared by two strategies counts once).
[[nodiscard]] std::vector<WorkEstimate> estimate_work(double x0, double y0, double x1, double y1,
                                                      const std::vector<Strategy>& strategies,
                                                      const FinishParams& params);

}  // namespace millnet::finish
