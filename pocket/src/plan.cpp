// The planner facade and the planners' registry (plan.hpp, planner_registry.hpp).
#include "millnet/pocket/plan.hpp"

#include "millnet/core/error.hpp"

namespace millnet::pocket {

const std::vector<PlannerEntry>& planners() {
  static const std::vector<PlannerEntry> registry{som_planner(), zigzag_planner(), offset_planner(),
                                                  adaptive_planner()};
  return registry;
}

std::vector<std::string> planner_names() {
  std::vector<std::string> names;
  for (const PlannerEntry& e : planners()) names.emplace_back(e.name);
  return names;
}

const PlannerEntry& planner_named(std::string_view name) {
  for (const PlannerEntry& e : planners())
    if (e.name == name) return e;
  std::string expected;
  for (const PlannerEntry& e : planners()) expected += (expected.empty() ? "" : ", ") + std::string(e.name);
  throw Error("unknown planner '" + std::string(name.substr(0, 40)) + "' (expected one of " + expected + ")");
}

PlannerSpec::PlannerSpec() : PlannerSpec(SomSpec{}) {}

std::string_view PlannerSpec::name() const { return entry_->name; }

PlanResult plan(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  return spec.entry().plan(region, cut, spec);
}

std::string_view planner_name(const PlannerSpec& spec) { return spec.name(); }

}  // namespace millnet::pocket
