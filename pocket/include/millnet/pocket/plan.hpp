#pragma once
// The planner facade: one call for every planner, chosen by a PlannerSpec — a planner and its typed
// parameters, from code (a planner's spec struct) or from a config (planner_registry.hpp).
//
//   PlanResult r = plan(region, cut, SomSpec{frame, som, smooth, path});
//   PlanResult z = plan(region, cut, ZigzagSpec{zigzag_params});
//   PlanResult a = plan(region, cut, planner_named("adaptive").parse(settings, {&cut, seed}));
//
// Adding a planner: docs/EXTENDING.md (its own header and source, one line in pocket/src/plan.cpp,
// its settings in the config schema).
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_adaptive.hpp"
#include "millnet/pocket/planner_offset.hpp"
#include "millnet/pocket/planner_registry.hpp"
#include "millnet/pocket/planner_som.hpp"
#include "millnet/pocket/planner_zigzag.hpp"

#include <string_view>

namespace millnet::pocket {

/// Plans one validated, normalized region with the planner `spec` names (pocket/planner.hpp contract).
[[nodiscard]] PlanResult plan(const Region& region, const CutParams& cut, const PlannerSpec& spec);

/// The planner's configuration name: "som", "zigzag", "offset" or "adaptive".
[[nodiscard]] std::string_view planner_name(const PlannerSpec& spec);

}  // namespace millnet::pocket
