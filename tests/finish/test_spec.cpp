// Strategy parameters derived from a surface specification (finish/spec.hpp), by hand.
#include "millnet/finish/spec.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace millnet;
using namespace millnet::finish;

TEST(SurfaceSpec, ThePassSpacingOfAScallopOnAPlaneIsTheBallsChord) {
  // Ø2 ball, h = 0.005: w = 2√(2·1·0.005 − 0.005²) = 0.199750 mm (the paper's p_f 0.2).
  EXPECT_NEAR(spec_spacing_mm(tooling::Cutter::ball(2), 0.005), 2 * std::sqrt(0.009975), 1e-12);
  EXPECT_NEAR(spec_spacing_mm(tooling::Cutter::ball(2), 0.005), 0.19975, 1e-5);
  // Bull Ø6 r1: its flat 4 mm plus the corner's chord.
  EXPECT_NEAR(spec_spacing_mm(tooling::Cutter::bull(6, 1), 0.005), 4 + 2 * std::sqrt(0.009975), 1e-12);
}

TEST(SurfaceSpec, EachStrategyDerivesItsOwnParameters) {
  SurfaceSpec spec;  // 0.005 mm scallop, 0.005 mm form tolerance
  FinishParams base;
  base.boundary_angle_deg = 30;
  base.stepover_mm = 0.7;  // written values that the spec replaces
  base.step_down_mm = 0.3;
  base.chord_tolerance_mm = 0.05;
  const double w = 2 * std::sqrt(0.009975);
  const double c30 = std::cos(std::numbers::pi / 6), s30 = 0.5;
  const FinishParams slope = params_for_spec(Strategy::SlopeMode, spec, base);
  EXPECT_NEAR(slope.stepover_mm, w * c30, 1e-12);   // 0.17299: passes w apart on a 30° slope
  EXPECT_NEAR(slope.step_down_mm, w * s30, 1e-12);  // 0.09988: levels w apart on a 30° wall
  EXPECT_EQ(slope.chord_tolerance_mm, 0.005);
  const FinishParams raster = params_for_spec(Strategy::Raster, spec, base);
  EXPECT_NEAR(raster.stepover_mm, w, 1e-12);
  EXPECT_EQ(raster.step_down_mm, 0.3);  // a raster has no step-down: kept
  const FinishParams scallop = params_for_spec(Strategy::ScallopMode, spec, base);
  EXPECT_EQ(scallop.scallop_mm, 0.005);
  EXPECT_NEAR(scallop.stepover_mm, w, 1e-12);
  const FinishParams z = params_for_spec(Strategy::Waterline, spec, base);
  EXPECT_NEAR(z.step_down_mm, w * s30, 1e-12);
  EXPECT_EQ(z.stepover_mm, 0.7);
  EXPECT_NEAR(params_for_spec(Strategy::Equidistant, spec, base).stepover_mm, w, 1e-12);
  // A steeper boundary: slope mode's raster spacing shrinks, its Z-levels widen.
  base.boundary_angle_deg = 60;
  const FinishParams steep = params_for_spec(Strategy::SlopeMode, spec, base);
  EXPECT_NEAR(steep.stepover_mm, w * 0.5, 1e-12);
  EXPECT_NEAR(steep.step_down_mm, w * c30, 1e-12);
}

TEST(SurfaceSpec, ABadSpecificationNamesItsKey) {
  SurfaceSpec spec;
  spec.scallop_mm = 0;
  try {
    (void)params_for_spec(Strategy::Raster, spec, FinishParams{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/finish/spec/scallop_mm"), std::string::npos);
  }
  spec = SurfaceSpec{};
  spec.out_of_spec_share = 1;
  EXPECT_THROW(spec.check(), Error);
}
