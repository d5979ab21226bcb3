#pragma once
// Named tolerances and fixed sizes of the datasets module (units in the names).
#include <cstddef>

namespace millnet::datasets::tol {

/// Narrowest wall (horizontal run, mm) the part generator gives a "vertical" wall. A truly vertical
/// wall cannot be a height field; 0.2 mm is far below the 1 mm sampling raster, so it reads as vertical.
inline constexpr double min_wall_run_mm = 0.2;

/// Margin (mm) kept between generated features (pads, pockets, bumps) and the footprint's edge.
inline constexpr double feature_margin_mm = 8.0;

}  // namespace millnet::datasets::tol

namespace millnet::datasets {

/// Output slots of a model vector (Korosec & Kopac: 5 strategies + 3 spare).
inline constexpr std::size_t kStrategySlots = 8;
/// Strategies the default training set covers (slots 1..5).
inline constexpr int kNamedStrategies = 5;

}  // namespace millnet::datasets
