#include "millnet/pocket/plan.hpp"

namespace millnet::pocket {

namespace {
template <class... F>
struct Overload : F... {
  using F::operator()...;
};
template <class... F>
Overload(F...) -> Overload<F...>;
}  // namespace

PlanResult plan(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  return std::visit(Overload{[&](const SomSpec& s) { return plan_som(region, cut, s.frame, s.som, s.smooth, s.path); },
                             [&](const ZigzagSpec& z) { return plan_zigzag(region, cut, z.zigzag); },
                             [&](const OffsetSpec& o) { return plan_offset(region, cut, o.offset); },
                             [&](const AdaptiveSpec& a) { return plan_adaptive(region, cut, a.adaptive); }},
                    spec);
}

std::string_view planner_name(const PlannerSpec& spec) {
  return std::visit(Overload{[](const SomSpec&) { return std::string_view("som"); },
                             [](const ZigzagSpec&) { return std::string_view("zigzag"); },
                             [](const OffsetSpec&) { return std::string_view("offset"); },
                             [](const AdaptiveSpec&) { return std::string_view("adaptive"); }},
                    spec);
}

}  // namespace millnet::pocket
