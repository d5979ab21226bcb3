#pragma once
// The surface a shop orders (issue 37 §2) and each strategy's parameters derived from it, as CAM
// systems derive them when given a cusp height instead of a stepover.
//
// A ball of radius R between passes a 3D distance w apart leaves a cusp h = R − √(R² − w²/4):
// the spec's largest scallop h gives w = 2√(2Rh − h²) (bull nose: its flat plus the corner's
// share; Ø2 ball and h = 0.005 mm: w = 0.1997 mm, the paper's p_f 0.2). On a slope θ across the
// passes an XY stepover s puts passes s / cos θ apart on the surface, and Z-levels Δz apart put
// them Δz / sin θ apart. So, with β the slope-mode boundary angle:
//
//   1 slope mode   shallow raster s = w·cos β, steep Z-levels Δz = w·sin β: in spec everywhere
//   2 raster       s = w (the flat formula, as CAM systems do): out of spec where the slope across
//                  the passes makes w / cos θ > the spec's spacing (walls)
//   3 scallop mode the spec's h, start spacing w: passes added where slopes need them
//   4 Z-level      Δz = w·sin β: in spec on walls at least β steep; shallower ground it leaves
//                  with larger cusps, flat floors it does not cut
//   5 equidistant  3D stepover w: in spec everywhere it reaches
//
// Every strategy's chord tolerance is the spec's form tolerance. Whether a strategy meets the spec
// is decided by simulation (simulate::SurfaceMetrics::spec_share), not by these formulas.
#include "millnet/finish/strategy.hpp"

#include <vector>

namespace millnet::finish {

struct SurfaceSpec {
  double scallop_mm = 0.005;         ///< largest cusp height between passes (the paper's case)
  double form_tolerance_mm = 0.005;  ///< path deviation allowed over the design (chord tolerance)
  double out_of_spec_share = 0.01;   ///< share of the machinable surface that may stay out of spec
  /// Material left over the design a cell may carry and be in spec: scallop + form tolerance, mm.
  [[nodiscard]] double limit_mm() const { return scallop_mm + form_tolerance_mm; }
  /// Throws millnet::Error naming the key (/finish/spec/…) when a value is not usable.
  void check() const;
};

/// The 3D distance between neighbouring passes of `tool` that leaves a cusp of `scallop_mm` on a
/// plane: ball 2√(2Rh − h²), bull (D − 2r) + 2√(2rh − h²), flat D. O(1).
[[nodiscard]] double spec_spacing_mm(const tooling::Cutter& tool, double scallop_mm);

/// `base` with the parameters `strategy` derives from `spec` (the table above); the rest of base
/// (tool, feeds, boundary angle, raster angle, frame) kept.
[[nodiscard]] FinishParams params_for_spec(Strategy strategy, const SurfaceSpec& spec, FinishParams base);

/// params_for_spec for each strategy, in order.
[[nodiscard]] std::vector<FinishParams> params_for_spec(const std::vector<Strategy>& strategies,
                                                        const SurfaceSpec& spec, const FinishParams& base);

}  // namespace millnet::finish
