// One registry per extension point (issue 36 §4): the config schema's enums, the CLI's choices and
// the modules' registries name the same things; a planner, strategy or dialect added to one and not
// the other fails here.
#include "config.hpp"
#include "json_settings.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/work.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using millnet::app::Json;

namespace {

std::vector<std::string> schema_enum(const std::string& pointer) {
  const Json* rule = &millnet::app::schema();
  for (std::size_t b = 1; b < pointer.size();) {
    std::size_t e = pointer.find('/', b);
    if (e == std::string::npos) e = pointer.size();
    rule = &(*rule)["properties"][pointer.substr(b, e - b)];
    b = e + 1;
  }
  return (*rule).at("enum").get<std::vector<std::string>>();
}

}  // namespace

TEST(Registries, TheDialectEnumIsTheDialectRegistry) {
  EXPECT_EQ(schema_enum("/machine/post"), millnet::gcode::dialect_names());
}

TEST(Registries, TheStrategyEnumIsTheStrategyRegistryAndAll) {
  EXPECT_EQ(schema_enum("/finish/strategy"), millnet::finish::strategy_choices());
  std::vector<std::string> slots;
  for (const auto& s : millnet::finish::strategy_registry()) {
    slots.push_back(std::to_string(static_cast<int>(s.id)));
    EXPECT_NE(s.sampling, 0u) << slots.back() << ": a strategy without a sampling grid has no work estimate";
  }
  EXPECT_EQ(slots, (std::vector<std::string>{"1", "2", "3", "4", "5"}));
}

TEST(Registries, ThePlannerEnumIsThePlannerRegistry) {
  EXPECT_EQ(schema_enum("/pocket/planner"), millnet::pocket::planner_names());
}

// Every planner of the registry reads its settings from the default config, and its spec names it;
// its work estimate comes before the feed map's (a planner without one would be refused nothing).
TEST(Registries, EveryPlannerParsesTheDefaultsAndEstimatesItsWork) {
  namespace pocket = millnet::pocket;
  const Json config = millnet::app::default_config(".");
  const millnet::app::JsonSettings settings(config["pocket"], "/pocket");
  pocket::CutParams cut;
  cut.tool.diameter = 6;
  cut.stepover = 2;
  cut.depth = 3;
  cut.step_down = 3;
  pocket::Region square;
  square.boundary = {{0, 0, 0}, {40, 0, 0}, {40, 30, 0}, {0, 30, 0}};
  std::vector<std::string> runs;
  for (const pocket::PlannerEntry& e : pocket::planners()) {
    const pocket::PlannerSpec spec = e.parse(settings, {&cut, 7});
    EXPECT_EQ(spec.name(), e.name);
    const auto work = pocket::estimate_work(square, cut, spec);
    ASSERT_GE(work.size(), 2u) << e.name;
    EXPECT_GT(work.front().count, 0) << e.name;
    EXPECT_EQ(work.back().unit, "feed-map cells") << e.name;
    for (const pocket::CompareRun& r : e.compare) runs.emplace_back(r.label);
  }
  EXPECT_EQ(runs, (std::vector<std::string>{"som", "zigzag-t", "zigzag-i", "offset", "adaptive"}));
  EXPECT_THROW((void)pocket::planner_named("spiral"), millnet::Error);
}

// A setting of the wrong type is named by its JSON pointer.
TEST(Registries, APlannerSettingOfTheWrongTypeIsNamed) {
  Json config = millnet::app::default_config(".");
  config["pocket"]["adaptive"]["step_mm"] = "fine";
  const millnet::app::JsonSettings settings(config["pocket"], "/pocket");
  millnet::pocket::CutParams cut;
  try {
    (void)millnet::pocket::planner_named("adaptive").parse(settings, {&cut, 7});
    FAIL() << "a string step_mm was accepted";
  } catch (const millnet::Error& e) {
    EXPECT_EQ(std::string(e.what()), "/pocket/adaptive/step_mm: expected a number, got string");
  }
}
