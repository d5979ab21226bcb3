#pragma once
// The roughing planners' registry (issue 36 §4): one entry per planner naming it, parsing its
// settings, estimating its work and planning. The command line's --planner choices, the schema's
// /pocket/planner enum (tests/app/test_registries.cpp), `millnet compare`'s runs and the work limits
// all come from it; nothing outside a planner's own files names its parameters.
//
//   const PlannerEntry& e = planner_named("adaptive");            // a name from a config
//   PlannerSpec spec = e.parse(pocket_settings, {&cut, seed});    // its settings, checked
//   PlanResult r = e.plan(region, cut, spec);                      // or pocket::plan(region, cut, spec)
//
// A planner's header defines its spec struct (its parameters, with `static constexpr
// std::string_view kPlanner`) and declares its entry (`PlannerEntry <name>_planner()`); its source
// defines them; pocket/src/plan.cpp lists the entry.
#include "millnet/core/budget.hpp"
#include "millnet/core/settings_view.hpp"
#include "millnet/pocket/planner.hpp"

#include <concepts>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace millnet::pocket {

struct PlannerEntry;

/// The registry's entry of a planner name; throws millnet::Error naming the accepted names.
[[nodiscard]] const PlannerEntry& planner_named(std::string_view name);

/// A planner's spec struct: its parameters and its registry name.
template <class Spec>
concept PlannerParams = requires {
  { Spec::kPlanner } -> std::convertible_to<std::string_view>;
};

/// A planner and its parameters (one planner's spec struct, e.g. SomSpec, or a registry entry's
/// parse). Cheap to copy: the parameters are shared and never change.
class PlannerSpec {
public:
  PlannerSpec();  ///< the SOM planner with default parameters
  template <PlannerParams Spec>
  PlannerSpec(Spec spec)  // implicit on purpose: plan(region, cut, SomSpec{…})
      : entry_(&planner_named(Spec::kPlanner)), params_(std::make_shared<const Spec>(std::move(spec))) {}
  [[nodiscard]] const PlannerEntry& entry() const { return *entry_; }
  /// The planner's registry name ("som", "zigzag", …).
  [[nodiscard]] std::string_view name() const;
  /// The parameters when this is that planner's spec, else nullptr.
  template <PlannerParams Spec>
  [[nodiscard]] const Spec* get() const {
    return name() == Spec::kPlanner ? static_cast<const Spec*>(params_.get()) : nullptr;
  }

private:
  const PlannerEntry* entry_;
  std::shared_ptr<const void> params_;
};

/// What a planner's settings parser knows besides its settings.
struct PlannerContext {
  const CutParams* cut = nullptr;  ///< the cut (its stepover spaces the SOM's grid)
  std::uint64_t seed = 7;          ///< the run's seed (/seed)
};

/// One run of `millnet compare`. Settings of the "pocket" section as "section/key" → value: the
/// defaults are set before the command line's flags (a flag wins), the overrides after them.
struct CompareRun {
  std::string_view label;
  std::vector<std::pair<std::string_view, std::string_view>> defaults;
  std::vector<std::pair<std::string_view, std::string_view>> overrides;
};

/// A planner of the registry.
struct PlannerEntry {
  std::string_view name;     ///< the config's /pocket/planner value
  std::string_view summary;  ///< one line for --help
  /// Its spec from the config's "pocket" section (checked against the schema, defaults filled).
  PlannerSpec (*parse)(const SettingsView& pocket, const PlannerContext& context) = nullptr;
  /// Plans one validated, normalized region (pocket/planner.hpp contract).
  PlanResult (*plan)(const Region& region, const CutParams& cut, const PlannerSpec& spec) = nullptr;
  /// Its own work before anything is allocated (machining's feed map is estimate_work's); the
  /// region is validated and not empty, the cut checked.
  std::vector<WorkEstimate> (*estimate)(const Region& region, const CutParams& cut, const PlannerSpec& spec) = nullptr;
  /// The runs `millnet compare` makes of it (most planners: one, its name, nothing set).
  std::vector<CompareRun> compare;
};

/// The registry, in the order the command line lists the planners.
[[nodiscard]] const std::vector<PlannerEntry>& planners();
/// The registry's names, in its order.
[[nodiscard]] std::vector<std::string> planner_names();

}  // namespace millnet::pocket
