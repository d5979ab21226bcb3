// Cutting data as a user meets it (issue 17): programs at the speed and feeds of the tool library ×
// the material table (hand-computed), each figure's source in the metrics, a written figure
// replacing the computed one, the 1995 preset reproducing the programs of before byte for byte,
// and one clear line (nothing written) for an unknown tool or material, a flute too short for the
// depth of cut, and figures outside the machine's limits.
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <nlohmann/json.hpp>

#include "testing/gcode_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>
#include <fstream>
#include <regex>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string bench(const std::string& name) {
  return std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json";
}

fs::path write_rect(const fs::path& d) {
  std::ofstream(d / "rect.json") << R"({"boundary": [[0,0,0],[80,0,0],[80,50,0],[0,50,0]], "islands": []})";
  return d / "rect.json";
}

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

/// The largest F word of a program.
double max_feed(const std::string& nc) {
  const std::regex f(R"(F([0-9.]+))");
  double m = 0;
  for (auto it = std::sregex_iterator(nc.begin(), nc.end(), f); it != std::sregex_iterator(); ++it)
    m = std::max(m, std::stod((*it)[1]));
  return m;
}

/// A 30 mm tall bump on a 20 × 20 mm block, as binary STL.
fs::path write_tall(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r2 = ((x - 10) * (x - 10) + (y - 10) * (y - 10)) / 49;
        return 1 + 29 * std::max(0.0, 1 - r2);
      },
      0, 20, 0, 20, 20, 20);
  const fs::path p = dir / "tall.stl";
  ingest::save_stl_binary(m, p);
  return p;
}

}  // namespace

// The programs of the bench pockets as millnet wrote them before it had cutting data (main at
// ddf3d95, tool Ø10, stepover 5, depth 5; tests/app/golden/shin-suh-1995/). On the machine and
// build that wrote them the preset reproduces them byte for byte. Another optimisation level or
// CPU may round a coordinate or a feed-map feed differently in its last written digit
// (-march=native, FMA contraction; see CMakeLists.txt), so the comparison is line by line: the same
// lines, comments identical, the same words in the same order, coordinates within 2e-4 mm (the 4
// decimals written) and the modal feed within 0.2 mm/min (F is written when it changes).
TEST(CliCutting, The1995PresetReproducesTheProgramsOfBefore) {
  const fs::path golden = fs::path(MILLNET_SOURCE_DIR) / "tests" / "app" / "golden" / "shin-suh-1995";
  const fs::path d = fresh_dir("cutting_preset");
  const std::string preset = std::string(MILLNET_SOURCE_DIR) + "/configs/presets/shin-suh-1995.json";
  std::size_t programs = 0;
  for (const auto& e : fs::directory_iterator(golden)) {
    const std::string tag = e.path().stem().string();  // comb.zigzag, four_islands.som.contour, …
    SCOPED_TRACE(tag);
    ++programs;
    const std::string pocket = tag.substr(0, tag.find('.'));
    const bool zigzag = tag.find("zigzag") != std::string::npos, contour = tag.find("contour") != std::string::npos;
    const auto r = run_millnet("pocket -q --config '" + preset + "' --pocket '" + bench(pocket) + "' --planner " +
                                   (zigzag ? "zigzag" : "som") + (contour ? " --contour" : "") +
                                   " --tool-diameter 10 --stepover 5 --depth 5 --out " + tag,
                               d);
    ASSERT_EQ(r.code, 0) << r.err;
    std::istringstream now(slurp(d / tag / (pocket + ".nc"))), then(slurp(e.path()));
    std::string a, b;
    double feed_a = 0, feed_b = 0;
    std::size_t line = 0;
    while (true) {
      const bool more_a = static_cast<bool>(std::getline(now, a)), more_b = static_cast<bool>(std::getline(then, b));
      ASSERT_EQ(more_a, more_b) << "the programs differ in length at line " << line + 1;
      if (!more_a) break;
      ++line;
      if (a.empty() || a[0] == '(' || b.empty() || b[0] == '(') {
        ASSERT_EQ(a, b) << "line " << line;
        continue;
      }
      std::istringstream wa(a), wb(b);
      std::vector<std::string> ta, tb;
      for (std::string w; wa >> w;) (w[0] == 'F' ? feed_a = std::stod(w.substr(1)) : (ta.push_back(w), 0.0));
      for (std::string w; wb >> w;) (w[0] == 'F' ? feed_b = std::stod(w.substr(1)) : (tb.push_back(w), 0.0));
      ASSERT_EQ(ta.size(), tb.size()) << "line " << line << ": " << a << " | " << b;
      for (std::size_t k = 0; k < ta.size(); ++k) {
        ASSERT_EQ(ta[k][0], tb[k][0]) << "line " << line << ": " << a << " | " << b;
        const bool coordinate = std::string("XYZIJ").find(ta[k][0]) != std::string::npos;
        if (coordinate)
          EXPECT_NEAR(std::stod(ta[k].substr(1)), std::stod(tb[k].substr(1)), 2e-4) << "line " << line;
        else
          EXPECT_EQ(ta[k], tb[k]) << "line " << line;
      }
      EXPECT_NEAR(feed_a, feed_b, 0.2) << "line " << line << ": " << a << " | " << b;
    }
    EXPECT_GT(line, 50u);
  }
  EXPECT_EQ(programs, 6u);
}

TEST(CliCutting, LibraryToolInAluminiumRunsAtTheHandComputedSpeedAndFeed) {
  const fs::path d = fresh_dir("cutting_library");
  const fs::path p = write_rect(d);
  const auto r = run_millnet("pocket -q --pocket '" + p.string() +
                                 "' --tool em10-3f-carbide --material aluminium-6061 --stepover 5 --depth 5 --out o",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string nc = slurp(d / "o" / "rect.nc");
  const json m = json::parse(slurp(d / "o" / "rect.metrics.json"));
  // Vc 300 m/min (6061, carbide, Ø6–12.5): n = 300000/(π·10) = 9549 rpm; f = 0.05·3·9549 = 1432 mm/min.
  EXPECT_NE(nc.find("S9549"), std::string::npos) << nc.substr(0, 800);
  EXPECT_NE(nc.find("half f2 1432 "), std::string::npos) << nc.substr(0, 800);
  EXPECT_NE(nc.find("(tool: em10-3f-carbide: D10 mm 3-flute carbide flat end mill)"), std::string::npos);
  EXPECT_NE(nc.find("aluminium-6061, Vc 300 m/min, fz 0.05 mm"), std::string::npos);
  const json& c = m.at("cutting_data");
  EXPECT_EQ(c["mode"], "library");
  EXPECT_EQ(c["tool"]["id"], "em10-3f-carbide");
  EXPECT_EQ(c["tool"]["from"], "flag --tool");
  EXPECT_EQ(c["material"]["from"], "flag --material");
  EXPECT_DOUBLE_EQ(c["figures"]["spindle_rpm"]["value"].get<double>(), 9549);
  EXPECT_DOUBLE_EQ(c["figures"]["feed_half"]["value"].get<double>(), 1432);
  EXPECT_NE(c["figures"]["feed_half"]["from"].get<std::string>().find("library"), std::string::npos);
  EXPECT_DOUBLE_EQ(m["parameters"]["spindle_rpm"].get<double>(), 9549);
  // Radial chip thinning lets light cuts run faster than f2, never beyond f2 × 3 or the machine.
  const double fmax = max_feed(nc);
  EXPECT_GT(fmax, 1432);
  EXPECT_LE(fmax, 3 * 1432 + 1e-9);
  if (fs::exists("/usr/bin/rs274")) {
    EXPECT_TRUE(millnet::testing::linuxcnc_accepts((d / "o" / "rect.nc").string()));
  }
}

TEST(CliCutting, AWrittenFigureReplacesTheComputedOneAndSaysWhereItCameFrom) {
  const fs::path d = fresh_dir("cutting_written");
  const fs::path p = write_rect(d);
  std::ofstream(d / "c.json") << R"({"pocket": {"tool": "em10-3f-carbide", "feed_half": 1000},
                                    "cutting": {"material": "steel-p20"}})";
  const auto r =
      run_millnet("pocket -q --config c.json --pocket '" + p.string() + "' --stepover 5 --depth 5 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const json c = json::parse(slurp(d / "o" / "rect.metrics.json")).at("cutting_data");
  EXPECT_EQ(c["figures"]["feed_half"]["from"], "config /pocket/feed_half");
  EXPECT_DOUBLE_EQ(c["figures"]["feed_half"]["value"].get<double>(), 1000);
  // P20 carbide Ø6–12.5: Vc 110 → n = 110000/(π·10) = 3501 rpm, from the library.
  EXPECT_DOUBLE_EQ(c["figures"]["spindle_rpm"]["value"].get<double>(), 3501);
  EXPECT_EQ(c["material"]["id"], "steel-p20");
  EXPECT_EQ(c["material"]["from"], "config /cutting/material");
}

TEST(CliCutting, BadToolMaterialOrLimitsGetOneLineAndNoFiles) {
  const fs::path d = fresh_dir("cutting_bad");
  const fs::path p = write_rect(d);
  std::ofstream(d / "fast.json") << R"({"pocket": {"spindle_rpm": 30000}})";
  std::ofstream(d / "slowspindle.json") << R"({"machine": {"min_spindle_rpm": 12000}})";
  struct Case {
    const char* name;
    std::string args;
    const char* expect;
  };
  const Case cases[] = {
      {"unknown_tool", "--tool em10-3f-carbid", "unknown tool id 'em10-3f-carbid' (did you mean 'em10-3f-carbide'?)"},
      {"unknown_material", "--tool em10-3f-carbide --material alu", "unknown material id 'alu'"},
      {"short_flutes", "--tool em3-2f-carbide --stepover 1.5 --depth 10 --step-down 10",
       "flute length 8 mm is shorter than the depth of cut per level 10 mm by 2 mm"},
      {"too_deep_for_stickout", "--tool em3-2f-carbide --stepover 1.5 --depth 25 --step-down 5",
       "the pocket reaches 25.00 mm below the stock top, beyond the tool's stick-out 20 mm by 5.00 mm"},
      {"rpm_over_machine", "--config ../fast.json --tool em10-3f-carbide",
       "spindle_rpm 30000 rpm exceeds the machine's /machine/max_spindle_rpm 24000 by 6000"},
      {"rpm_below_machine", "--config ../slowspindle.json --tool em10-3f-carbide",
       "rpm is below the machine's minimum 12000 rpm by 2451 rpm"},
      {"ball_for_roughing", "--tool bn6-2f-carbide", "cannot rough a pocket"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path w = d / c.name;
    const auto r = run_millnet("pocket -q --pocket '" + p.string() + "' " + c.args + " --out o", w);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_EQ(list_files(w / "o"), "");
  }
  // --tool and --tool-diameter name the tool twice.
  const auto both = run_millnet(
      "pocket -q --pocket '" + p.string() + "' --tool em10-3f-carbide --tool-diameter 6 --out o", d / "both");
  EXPECT_EQ(both.code, 2) << both.err;
}

TEST(CliCutting, APartDeeperThanTheToolsStickOutIsRefusedByRoughAndFinish) {
  const fs::path d = fresh_dir("cutting_stickout");
  const fs::path mesh = write_tall(d);
  // 30 mm of part + 1 mm of stock on top: 31 mm below the stock top; em3-2f-carbide sticks out 20 mm.
  auto r = run_millnet("rough -q --mesh '" + mesh.string() + "' --tool em3-2f-carbide --stepover 1.5 --out o", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("the part reaches 31.00 mm below the stock top, beyond the tool's stick-out 20 mm"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(list_files(d / "o"), "");
  // A Ø6 ball that sticks out 35 mm reaches it.
  std::ofstream(d / "tools.json") << R"({"tools": [{"id": "short-ball", "type": "ball", "diameter": 6, "flutes": 2,
                                        "tool_material": "carbide", "flute_length": 10, "stickout": 25}]})";
  std::ofstream(d / "c.json") << R"({"cutting": {"tools_file": "tools.json"}})";
  r = run_millnet("finish -q --config c.json --mesh '" + mesh.string() + "' --tool short-ball --strategy 2 --out f", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  // Finishing is checked on what it machines (issue 38): its lowest cut is on the part's surround at
  // z = 1, 30 mm below the stock top (not the base at 31 mm, which only the outside walls reach).
  EXPECT_NE(r.err.find("the finishing's lowest cut (2 3D finishing (parallel)) reaches 30.00 mm below the stock top, "
                       "beyond the tool's stick-out 25 mm by 5.00 mm"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(list_files(d / "f"), "");
  // The library's Ø6 ball (stick-out 35 mm) finishes it, at its cutting data, and names itself.
  r = run_millnet("finish -q --mesh '" + mesh.string() +
                      "' --tool bn6-2f-carbide --material steel-p20 --strategy 2 "
                      "--stepover 1 --out g",
                  d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string nc = slurp(d / "g" / "tall.s2.nc");
  EXPECT_NE(nc.find("(tool: bn6-2f-carbide: D6 mm 2-flute carbide ball-nose end mill)"), std::string::npos)
      << nc.substr(0, 600);
  const json c = json::parse(slurp(d / "g" / "tall.s2.metrics.json")).at("cutting_data");
  // P20, carbide Ø6–12.5: Vc 110, fz 0.035; a_p = the finishing stock 0.1 mm ⇒ D_eff = 2·√(0.1·5.9) = 1.5362 mm,
  // n = 110000/(π·1.5362) = 22792 rpm (under the machine's 24,000), f = 0.035·2·22792 = 1595 mm/min.
  EXPECT_NEAR(c["d_eff_mm"].get<double>(), 2 * std::sqrt(0.1 * 5.9), 1e-9);
  EXPECT_DOUBLE_EQ(c["figures"]["spindle_rpm"]["value"].get<double>(), 22792);
  EXPECT_DOUBLE_EQ(c["figures"]["feed_mm_min"]["value"].get<double>(), 1595);
  EXPECT_NE(nc.find("S22792"), std::string::npos);
}

// Issue 38: a tool given only by its diameter had no stick-out and was never checked. It takes the
// library's tool of its shape (Ø3 flat: em3-2f-carbide, 20 mm), else /cutting/inline_stickout_mm.
TEST(CliCutting, AToolGivenByItsDiameterIsCheckedWithTheLibrarysStickOut) {
  const fs::path d = fresh_dir("cutting_inline_stickout");
  const fs::path mesh = write_tall(d);  // 31 mm below the stock top
  auto r = run_millnet("rough -q --mesh '" + mesh.string() + "' --tool-diameter 3 --stepover 1.5 --out o", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("beyond the tool's stick-out 20 mm by 11.00 mm"), std::string::npos) << r.err;
  EXPECT_EQ(list_files(d / "o"), "");
  // No Ø7 ball in the library: the default stick-out, 25 mm here, refuses it; 40 mm (the default) reaches.
  std::ofstream(d / "c.json") << R"({"cutting": {"inline_stickout_mm": 25}})";
  r = run_millnet("finish -q --config c.json --mesh '" + mesh.string() + "' --tool ball:7 --strategy 2 --out f", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("beyond the tool's stick-out 25 mm by 5.00 mm"), std::string::npos) << r.err;
  EXPECT_EQ(list_files(d / "f"), "");
  r = run_millnet("finish -q --mesh '" + mesh.string() + "' --tool ball:7 --strategy 2 --stepover 2 --out g", d);
  EXPECT_EQ(r.code, 0) << r.err;
  // The roughing stops /rough/floor_allowance_mm above the base: 31 − 12 = 19 mm, within em3's 20.
  std::ofstream(d / "floor.json") << R"({"rough": {"floor_allowance_mm": 12}})";
  r = run_millnet(
      "rough -q --config floor.json --mesh '" + mesh.string() + "' --tool em3-2f-carbide --stepover 1.5 --out h", d);
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(CliCutting, AShopLibraryAddsToolsAndIsCheckedLikeAConfig) {
  const fs::path d = fresh_dir("cutting_shop");
  const fs::path p = write_rect(d);
  std::ofstream(d / "tools.json") << R"({"tools": [{"id": "shop-em8", "type": "flat", "diameter": 8, "flutes": 4,
                                        "tool_material": "carbide", "flute_length": 20, "stickout": 30}]})";
  std::ofstream(d / "c.json") << R"({"cutting": {"tools_file": "tools.json"}})";
  auto r = run_millnet(
      "pocket -q --config c.json --pocket '" + p.string() + "' --tool shop-em8 --stepover 4 --depth 5 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const json c = json::parse(slurp(d / "o" / "rect.metrics.json")).at("cutting_data");
  EXPECT_EQ(c["tool"]["flutes"], 4);
  // 6061 carbide Ø6–12.5: n = 300000/(π·8) = 11937 rpm, f = 0.05·4·11937 = 2387 mm/min.
  EXPECT_DOUBLE_EQ(c["figures"]["spindle_rpm"]["value"].get<double>(), 11937);
  EXPECT_DOUBLE_EQ(c["figures"]["feed_half"]["value"].get<double>(), 2387);
  // A misspelt key of the shop's file: one line naming the file and the key.
  std::ofstream(d / "bad_tools.json") << R"({"tools": [{"id": "x", "type": "flat", "diameter": 8, "flutez": 4,
                                            "tool_material": "carbide"}]})";
  std::ofstream(d / "bad.json") << R"({"cutting": {"tools_file": "bad_tools.json"}})";
  r = run_millnet("pocket -q --config bad.json --pocket '" + p.string() + "' --tool x --out o2", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("bad_tools.json: /tools/0/flutez: unknown key"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "o2"));
}

}  // namespace millnet::testing
