#pragma once
// The planner facade: one call for every planner, chosen by a typed spec (no planner names as
// strings across the seam).
//
//   PlanResult r = plan(region, cut, SomSpec{frame, som, smooth});
//   PlanResult z = plan(region, cut, ZigzagSpec{zigzag_params});
//   PlanResult a = plan(region, cut, AdaptiveSpec{adaptive_params});
//
// Adding a planner: its params struct and plan_<name>() in pocket (a header and a .cpp), a spec
// struct here, one alternative in PlannerSpec, and one line in plan() / planner_name().
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_adaptive.hpp"
#include "millnet/pocket/planner_offset.hpp"
#include "millnet/pocket/planner_som.hpp"
#include "millnet/pocket/planner_zigzag.hpp"

#include <string_view>
#include <variant>

namespace millnet::pocket {

/// The SOM planner (grid tool points → self-organising tour → smoothing).
struct SomSpec {
  GridFrame frame;
  SomParams som;
  SmoothingParams smooth;
  SomPathParams path;  ///< wall rings and corner arcs (issue 11)
};

/// The zigzag planner with T- or I-partition.
struct ZigzagSpec {
  ZigzagParams zigzag;
};

/// The offset (contour-parallel) planner: rings at the stepover, inside out, walls included.
struct OffsetSpec {
  OffsetParams offset;
};

/// The adaptive (constant-engagement) planner: passes that keep the engagement at a target angle.
struct AdaptiveSpec {
  AdaptiveParams adaptive;
};

using PlannerSpec = std::variant<SomSpec, ZigzagSpec, OffsetSpec, AdaptiveSpec>;

/// Plans one validated, normalized region with the planner `spec` names (pocket/planner.hpp contract).
[[nodiscard]] PlanResult plan(const Region& region, const CutParams& cut, const PlannerSpec& spec);

/// The planner's configuration name: "som", "zigzag", "offset" or "adaptive".
[[nodiscard]] std::string_view planner_name(const PlannerSpec& spec);

}  // namespace millnet::pocket
