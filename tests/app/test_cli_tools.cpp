// millnet tools import / export as a user runs them (issue 40): a shop's LinuxCNC, FreeCAD and
// Fusion 360 tables become a tool library the schema accepts and /cutting/tools_file reads; the
// config's library becomes a LinuxCNC tool table; a bad file is one line, exit 1, nothing written.
#include "app/cli_runner.hpp"
#include "config.hpp"
#include "cutting.hpp"

#include "millnet/tooling/cutting.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string data(const std::string& rel) {
  return "'" + std::string(MILLNET_SOURCE_DIR) + "/tests/tooling/data/" + rel + "'";
}

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

/// The tool of `doc["tools"]` with this number.
const json& numbered(const json& doc, int number) {
  for (const json& t : doc["tools"])
    if (t.value("number", 0) == number) return t;
  throw std::runtime_error("no T" + std::to_string(number));
}

}  // namespace

TEST(CliTools, ImportsEachFormatIntoALibraryTheSchemaAccepts) {
  const fs::path d = fresh_dir("tools_import");
  struct Case {
    std::string file, format, extra;
    std::size_t tools;
  };
  for (const Case& c :
       {Case{"linuxcnc/tool.tbl", "linuxcnc", "", 5}, Case{"linuxcnc/inch.tbl", "linuxcnc", "--units inch", 3},
        Case{"freecad/Library/Shop.fctl", "freecad", "", 5}, Case{"freecad/Bit/6mm_Bullnose.fctb", "freecad", "", 1},
        Case{"fusion/library.json", "fusion", "", 4}}) {
    SCOPED_TRACE(c.file);
    const auto r =
        run_millnet("tools import " + data(c.file) + " --format " + c.format + " " + c.extra + " --out lib.json", d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("note: "), std::string::npos) << "what was assumed is said";
    EXPECT_NE(r.err.find("tools import: " + std::to_string(c.tools) + " tools"), std::string::npos) << r.err;
    app::Json doc = app::read_json(d / "lib.json");
    EXPECT_EQ(doc["tools"].size(), c.tools);
    EXPECT_NE(doc["comment"].get<std::string>().find("Imported from"), std::string::npos);
    EXPECT_NO_THROW(app::check_tool_library(doc, "lib.json"));
  }
  // Hand-checked figures of the last one (Fusion: T3 in inches, its holder).
  const app::Json doc = app::read_json(d / "lib.json");
  const json& ball = numbered(doc, 3);
  EXPECT_EQ(ball["type"], "ball");
  EXPECT_DOUBLE_EQ(ball["diameter"].get<double>(), 6.35);
  EXPECT_EQ(ball["length_offset"], 13);
  EXPECT_DOUBLE_EQ(ball["holder_diameter"].get<double>(), 31.75);
  EXPECT_DOUBLE_EQ(numbered(doc, 5)["point_angle"].get<double>(), 135);
}

TEST(CliTools, ExportWritesTheBuiltInLibraryAsALinuxCncTable) {
  const fs::path d = fresh_dir("tools_export");
  const auto r = run_millnet("tools export --format linuxcnc --out tool.tbl", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string tbl = slurp(d / "tool.tbl");
  EXPECT_EQ(lines(tbl), 12U) << tbl;  // the header and T1..T11
  EXPECT_NE(tbl.find("\nT1 P1 D3 Z0 ;em3-2f-carbide: flat 2F\n"), std::string::npos) << tbl;
  EXPECT_NE(tbl.find("\nT6 P6 D10 Z0 ;br10r1-4f-carbide: bull r1 4F\n"), std::string::npos) << tbl;
  EXPECT_NE(tbl.find("\nT10 P10 D10 Z0 ;dr10-hss: drill 2F hss\n"), std::string::npos) << tbl;
  EXPECT_NE(tbl.find("\nT11 P11 D1 Z0 ;bn1-2f-carbide: ball 2F\n"), std::string::npos) << tbl;
}

TEST(CliTools, ExportOfAnImportedTableKeepsTheShopsToolsOnTheirNumbers) {
  const fs::path d = fresh_dir("tools_roundtrip");
  ASSERT_EQ(run_millnet("tools import " + data("linuxcnc/tool.tbl") + " --format linuxcnc --out shop.json -q", d).code,
            0);
  std::ofstream(d / "c.json") << R"({"cutting": {"tools_file": "shop.json"}})";
  const auto r = run_millnet("tools export --format linuxcnc --config c.json --out tool.tbl", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string tbl = slurp(d / "tool.tbl");
  // T1..T5 are the shop's; the built-in T1..T5 are left out (and said so); T6..T11 stay.
  EXPECT_NE(tbl.find("\nT1 P1 D6 Z0 ;6mm-end-mill-3f-carbide: flat 3F\n"), std::string::npos) << tbl;
  EXPECT_NE(tbl.find("\nT5 P5 D3.175 Z0 ;t5: flat 2F\n"), std::string::npos) << tbl;
  EXPECT_NE(tbl.find("\nT6 P6 D10 Z0 ;br10r1-4f-carbide"), std::string::npos) << tbl;
  EXPECT_EQ(tbl.find("em3-2f-carbide"), std::string::npos) << tbl;
  EXPECT_EQ(lines(tbl), 12U);
  EXPECT_NE(r.err.find("note: built-in tool em3-2f-carbide (T1) left out: T1 is 6mm-end-mill-3f-carbide of"),
            std::string::npos)
      << r.err;
  // And the table reads back into the same tools (import → export → import).
  ASSERT_EQ(run_millnet("tools import tool.tbl --format linuxcnc --out again.json -q", d).code, 0);
  const app::Json first = app::read_json(d / "shop.json"), again = app::read_json(d / "again.json");
  for (const json& t : first["tools"]) {
    const json& u = numbered(again, t["number"].get<int>());
    EXPECT_EQ(u["id"], t["id"]);
    EXPECT_EQ(u["type"], t["type"]);
    EXPECT_EQ(u["diameter"], t["diameter"]);
    EXPECT_EQ(u["corner_radius"], t["corner_radius"]);
    EXPECT_EQ(u["flutes"], t["flutes"]);
    EXPECT_EQ(u["tool_material"], t["tool_material"]);
  }
}

TEST(CliTools, BadFilesAreOneLineExitOneAndNothingWritten) {
  const fs::path d = fresh_dir("tools_bad");
  std::ofstream(d / "bad.tbl") << "T1 P1 D6 ;ok\nT2 P2 Z1 ;no diameter\n";
  std::ofstream(d / "bad.json") << R"({"data": [{"type": "flat end mill", "unit": "cubits", "geometry": {"DC": 6}}]})";
  std::ofstream(d / "bad.fctb")
      << R"({"version": 2, "name": "x", "shape": "endmill.fcstd", "parameter": {"Length": "5 mm"}})";
  struct Case {
    std::string args, expect;
  };
  for (const Case& c : {Case{"bad.tbl --format linuxcnc", "bad.tbl:2: T2: no D word"},
                        Case{"bad.json --format fusion", "bad.json: /data/0/unit: 'cubits'"},
                        Case{"bad.fctb --format freecad", "bad.fctb: /parameter/Diameter: missing"},
                        Case{"missing.tbl --format linuxcnc", "missing.tbl: no such file"},
                        Case{"bad.json --format fusion --units inch", "--units applies to --format linuxcnc"},
                        Case{"bad.tbl --format heidenhain", "--format"}}) {
    SCOPED_TRACE(c.args);
    const auto r = run_millnet("tools import " + c.args + " --out lib.json", d);
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1U) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "lib.json"));
  }
  // A shop library with a tool without a number: the export names it and writes nothing.
  std::ofstream(d / "shop.json") << R"({"tools": [{"id": "shop-em8", "type": "flat", "diameter": 8, "flutes": 4,
                                      "tool_material": "carbide"}]})";
  std::ofstream(d / "c.json") << R"({"cutting": {"tools_file": "shop.json"}})";
  const auto r = run_millnet("tools export --format linuxcnc --config c.json --out tool.tbl", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1U) << r.err;
  EXPECT_NE(r.err.find("1 tool(s) without a number (T): 'shop-em8'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "tool.tbl"));
  // Two tools of one file on one number: refused when the library is read (every command).
  std::ofstream(d / "dup.json") << R"({"tools": [
      {"id": "a", "type": "flat", "diameter": 8, "flutes": 4, "tool_material": "carbide", "number": 3},
      {"id": "b", "type": "flat", "diameter": 6, "flutes": 4, "tool_material": "carbide", "number": 3}]})";
  std::ofstream(d / "c2.json") << R"({"cutting": {"tools_file": "dup.json"}})";
  const auto dup = run_millnet("tools export --format linuxcnc --config c2.json --out tool.tbl", d);
  EXPECT_EQ(dup.code, 1);
  EXPECT_NE(dup.err.find("dup.json: /tools/1/number: T3 is also /tools/0 (a)"), std::string::npos) << dup.err;
  // Usage errors: a missing flag or subcommand.
  EXPECT_EQ(run_millnet("tools import bad.tbl --format linuxcnc", d).code, 2);
  EXPECT_EQ(run_millnet("tools", d).code, 2);
  EXPECT_EQ(run_millnet("tools export --out tool.tbl", d).code, 2);
  EXPECT_FALSE(fs::exists(d / "tool.tbl"));
}

TEST(CliTools, HolderNarrowerThanTheToolIsRefusedNamingTheKey) {
  const fs::path d = fresh_dir("tools_holder");
  std::ofstream(d / "shop.json") << R"({"tools": [{"id": "em8", "type": "flat", "diameter": 8, "flutes": 4,
      "tool_material": "carbide", "number": 1, "holder_diameter": 6, "holder_length": 40}]})";
  std::ofstream(d / "c.json") << R"({"cutting": {"tools_file": "shop.json"}})";
  const auto r = run_millnet("tools export --format linuxcnc --config c.json --out tool.tbl", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("shop.json: /tools/0 em8: holder diameter 6 mm is narrower than the tool (8 mm)"),
            std::string::npos)
      << r.err;
}

// The built-in tools got numbers and holders, not new labels: program headers name them as before.
TEST(CliTools, BuiltInToolsHaveDistinctNumbersHoldersAndTheirOldLabels) {
  const app::ToolLibrary lib = app::tool_library(app::default_config(MILLNET_SOURCE_DIR));
  ASSERT_EQ(lib.tools.size(), 11U);
  std::vector<int> numbers;
  for (const tooling::Tool& t : lib.tools) {
    numbers.push_back(t.number);
    EXPECT_GE(t.holder_diameter_mm, 1.5 * t.diameter_mm) << t.id;
    EXPECT_GT(t.holder_length_mm, 0) << t.id;
  }
  std::sort(numbers.begin(), numbers.end());
  for (int i = 0; i < 11; ++i) EXPECT_EQ(numbers[static_cast<std::size_t>(i)], i + 1);
  EXPECT_EQ(lib.tool("em10-3f-carbide", "test").label(), "em10-3f-carbide: D10 mm 3-flute carbide flat end mill");
  EXPECT_EQ(lib.tool("bn2-2f-carbide", "test").label(), "bn2-2f-carbide: D2 mm 2-flute carbide ball-nose end mill");
  EXPECT_EQ(lib.tool("br10r1-4f-carbide", "test").label(),
            "br10r1-4f-carbide: D10 mm r1 4-flute carbide bull-nose end mill");
  EXPECT_EQ(lib.tool("dr10-hss", "test").label(), "dr10-hss: D10 mm 2-flute hss drill");
}

TEST(CliTools, SchemaRangesAreTheToolsOwn) {
  const app::Json schema = app::read_json(fs::path(MILLNET_SOURCE_DIR) / "configs/schema/tools.schema.json");
  const app::Json& p = schema["properties"]["tools"]["items"]["properties"];
  EXPECT_EQ(p["number"]["maximum"].get<int>(), tooling::kMaxToolNumber);
  EXPECT_EQ(p["length_offset"]["maximum"].get<int>(), tooling::kMaxToolNumber);
  EXPECT_EQ(p["holder_diameter"]["maximum"].get<double>(), tooling::kMaxHolderMm);
  EXPECT_EQ(p["holder_length"]["maximum"].get<double>(), tooling::kMaxHolderMm);
}

}  // namespace millnet::testing
