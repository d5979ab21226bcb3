// Config checking: strict keys and types named by their JSON pointer, defaults, path resolution.
#include "config.hpp"
#include "cutting.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using millnet::app::Json;

namespace {
std::string error_of(Json config) {
  try {
    millnet::app::check_config(config, "/base", "cfg.json");
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Config, UnknownKeyIsRejectedWithItsPath) {
  const std::string e = error_of(Json::parse(R"({"train": {"alpah": 1}})"));
  EXPECT_NE(e.find("cfg.json"), std::string::npos) << e;
  EXPECT_NE(e.find("/train/alpah"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Config, WrongTypeIsRejectedWithItsPath) {
  const std::string e = error_of(Json::parse(R"({"pocket": {"tool_diameter": "ten"}})"));
  EXPECT_NE(e.find("/pocket/tool_diameter"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  const std::string e2 = error_of(Json::parse(R"({"dataset": {"grid": 15.5}})"));
  EXPECT_NE(e2.find("/dataset/grid: expected an integer"), std::string::npos) << e2;
  const std::string e3 = error_of(Json::parse(R"({"dataset": {"augment": {"axes": ["x", "w"]}}})"));
  EXPECT_NE(e3.find("/dataset/augment/axes/1"), std::string::npos) << e3;
}

TEST(Config, RangesAndEnumsAreChecked) {
  EXPECT_NE(error_of(Json::parse(R"({"pocket": {"tool_diameter": 0}})")).find("must be >"), std::string::npos);
  EXPECT_NE(error_of(Json::parse(R"({"train": {"loo": "row"}})")).find("expected one of"), std::string::npos);
  EXPECT_NE(error_of(Json::parse(R"({"dataset": {"parts": [{"label": 1}]}})")).find("/dataset/parts/0/file: required"),
            std::string::npos);
}

TEST(Config, DefaultsAreFilledAndPathsResolvedAgainstTheConfigFolder) {
  Json c = Json::parse(R"({"output": "results", "predict": {"parts": ["a/b.stl", "/abs/c.stl"]}})");
  millnet::app::check_config(c, "/base/configs", "cfg.json");
  EXPECT_EQ(c["output"], "/base/configs/results");
  EXPECT_EQ(c["predict"]["parts"][0], "/base/configs/a/b.stl");
  EXPECT_EQ(c["predict"]["parts"][1], "/abs/c.stl");
  EXPECT_EQ(c["pocket"]["tool_diameter"], 10.0);
  EXPECT_EQ(c["dataset"]["grid"], 15);
  EXPECT_EQ(c["dataset"]["augment"]["angles_deg"].size(), 11u);
  EXPECT_EQ(c["train"]["loo"], "part");
}

TEST(Config, EveryShippedConfigValidates) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(MILLNET_SOURCE_DIR) / "configs")) {
    if (e.path().extension() != ".json" || e.path().parent_path().filename() == "schema") continue;
    const std::string name = e.path().filename().string();
    if (name == "tools.json" || name == "materials.json") continue;  // their own schemas (below)
    EXPECT_NO_THROW((void)millnet::app::load_config(e.path())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 6);  // default, pocket, predict, rough, train, presets/shin-suh-1995
}

TEST(Config, TheShippedToolLibraryAndMaterialTableValidateAndAreComplete) {
  const fs::path dir = fs::path(MILLNET_SOURCE_DIR) / "configs";
  nlohmann::json tools = millnet::app::read_json(dir / "tools.json");
  nlohmann::json mats = millnet::app::read_json(dir / "materials.json");
  EXPECT_NO_THROW(millnet::app::check_tool_library(tools, "tools.json"));
  EXPECT_NO_THROW(millnet::app::check_material_table(mats, "materials.json"));
  // The issue's materials, each with a source on every row, covering carbide from 0 to 1000 mm.
  std::set<std::string> ids;
  for (const auto& m : mats["materials"]) {
    ids.insert(m["id"].get<std::string>());
    double covered = 0;
    for (const auto& r : m["cutting"]) {
      EXPECT_FALSE(r["source"].get<std::string>().empty()) << m["id"];
      if (r["tool_material"] == "carbide" && r["d_min"].get<double>() == covered) covered = r["d_max"].get<double>();
    }
    EXPECT_EQ(covered, 1000) << m["id"] << ": carbide rows leave a gap";
  }
  for (const char* id : {"aluminium-6061", "aluminium-7075", "steel-free-cutting", "steel-p20", "stainless-304",
                         "cast-iron-grey", "brass", "pom", "machining-wax", "steel-hardened-54hrc"})
    EXPECT_TRUE(ids.count(id)) << id;
  // The default config's tools exist in the library.
  std::set<std::string> tool_ids;
  for (const auto& t : tools["tools"]) tool_ids.insert(t["id"].get<std::string>());
  EXPECT_TRUE(tool_ids.count("em10-3f-carbide"));
  EXPECT_TRUE(tool_ids.count("bn2-2f-carbide"));
}

TEST(Config, InvalidJsonNamesLine) {
  const fs::path p = fs::temp_directory_path() / "millnet_test_bad_config.json";
  { std::ofstream(p) << "{\n  \"seed\": 7,\n  \"train\": {\n    \"loo\": \"part\",,\n  }\n}\n"; }
  try {
    (void)millnet::app::load_config(p);
    FAIL() << "no error";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.string() + ":4:"), std::string::npos) << e.what();
  }
  fs::remove(p);
}

namespace {
// Every number/integer rule under `rule` (items of arrays too) without a lower and an upper bound.
void unbounded(const Json& rule, const std::string& ptr, std::vector<std::string>& out) {
  const std::string type = rule.value("type", "");
  if (type == "object" && rule.contains("properties"))
    for (auto it = rule["properties"].begin(); it != rule["properties"].end(); ++it)
      unbounded(it.value(), ptr + "/" + it.key(), out);
  if (type == "array" && rule.contains("items")) unbounded(rule["items"], ptr + "/*", out);
  if (type == "number" || type == "integer" || type == "integer_or_string")
    if (!(rule.contains("minimum") || rule.contains("exclusiveMinimum")) ||
        !(rule.contains("maximum") || rule.contains("exclusiveMaximum")))
      out.push_back(ptr);
}
}  // namespace

// Issue 15: "every numeric key has a documented finite range" (1e307 for /pocket/som/w corrupted
// the heap, 100000 threads crashed OpenMP, 2^32+1 parts per family became 1). A new key without
// both bounds fails here, naming it.
TEST(Config, EveryNumericKeyHasAFiniteRange) {
  std::vector<std::string> missing;
  unbounded(millnet::app::schema(), "", missing);
  std::string list;
  for (const auto& m : missing) list += m + "\n";
  EXPECT_TRUE(missing.empty()) << "numeric keys without minimum and maximum:\n" << list;
}
