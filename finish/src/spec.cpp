// Strategy parameters from a surface specification (spec.hpp).
#include "millnet/finish/spec.hpp"

#include "sampling.hpp"

#include "millnet/core/error.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace millnet::finish {

void SurfaceSpec::check() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(scallop_mm)) throw Error("/finish/spec/scallop_mm: must be > 0 mm");
  if (!positive(form_tolerance_mm)) throw Error("/finish/spec/form_tolerance_mm: must be > 0 mm");
  if (!(out_of_spec_share >= 0 && out_of_spec_share < 1))
    throw Error("/finish/spec/out_of_spec_share: must be in [0, 1)");
}

double spec_spacing_mm(const tooling::Cutter& tool, double scallop_mm) {
  return detail::scallop_spacing(tool, scallop_mm);
}

FinishParams params_for_spec(Strategy strategy, const SurfaceSpec& spec, FinishParams base) {
  spec.check();
  const double w = spec_spacing_mm(base.tool, spec.scallop_mm);
  const double beta = base.boundary_angle_deg * std::numbers::pi / 180;
  base.chord_tolerance_mm = spec.form_tolerance_mm;
  switch (strategy) {
    case Strategy::SlopeMode:
      base.stepover_mm = w * std::cos(beta);
      base.step_down_mm = w * std::sin(beta);
      break;
    case Strategy::Raster: base.stepover_mm = w; break;
    case Strategy::ScallopMode:
      base.scallop_mm = spec.scallop_mm;
      base.stepover_mm = w;
      break;
    case Strategy::Waterline: base.step_down_mm = w * std::sin(beta); break;
    case Strategy::Equidistant: base.stepover_mm = w; break;
  }
  return base;
}

std::vector<FinishParams> params_for_spec(const std::vector<Strategy>& strategies, const SurfaceSpec& spec,
                                          const FinishParams& base) {
  std::vector<FinishParams> out;
  out.reserve(strategies.size());
  for (const Strategy s : strategies) out.push_back(params_for_spec(s, spec, base));
  return out;
}

}  // namespace millnet::finish
