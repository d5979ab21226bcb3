#pragma once
// What the planners' work estimates share (work.cpp): the region's box and the refusal's wording.
#include "geometry_internal.hpp"
#include "millnet/pocket/planner.hpp"

#include <string>

namespace millnet::pocket::detail {

/// The box of the region's boundary (islands lie inside it).
[[nodiscard]] BBox boundary_box(const Region& region);

/// "stepover 0.5 mm over a 100 × 60 mm pocket": what an estimate's count follows from.
[[nodiscard]] std::string over(const std::string& key, double value, const BBox& box);

/// A length as estimates print it.
[[nodiscard]] std::string mm(double v);

}  // namespace millnet::pocket::detail
