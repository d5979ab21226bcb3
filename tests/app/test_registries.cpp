// One registry per extension point (issue 36 §4): the config schema's enums, the CLI's choices and
// the modules' registries name the same things; a planner, strategy or dialect added to one and not
// the other fails here.
#include "config.hpp"

#include "millnet/finish/strategy.hpp"
#include "millnet/gcode/writer.hpp"

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
