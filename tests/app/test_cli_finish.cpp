// millnet finish and millnet simulate as a user runs them: the files of the contract, programs
// LinuxCNC accepts, the roughing frame (Z 0 = part top + 1 mm), no gouge in the simulated
// surface, a gouge reported at its G-code line, and one clear line for bad input with nothing
// half-written.
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"

#include <nlohmann/json.hpp>

#include "testing/gcode_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <utility>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;

/// A solid under z = f(x, y) over 16 × 12 mm (nx × ny samples) as ASCII STL DIR/NAME.stl.
fs::path write_solid(const fs::path& dir, const std::string& name, const std::function<double(double, double)>& f,
                     int nx, int ny) {
  const auto m = testing_ingest::solid(f, 0, 16, 0, 12, nx, ny);
  const fs::path p = dir / (name + ".stl");
  std::ofstream out(p);
  out << "solid " << name << "\n";
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto v = m.V.row(m.F(f, k));
      out << "   vertex " << v(0) << " " << v(1) << " " << v(2) << "\n";
    }
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid " << name << "\n";
  return p;
}

/// A dome (max 6 mm) on a 16 × 12 mm block 1 mm thick, as ASCII STL.
fs::path write_dome(const fs::path& dir) {
  return write_solid(
      dir, "dome",
      [](double x, double y) {
        const double r2 = (x - 8) * (x - 8) / 36 + (y - 6) * (y - 6) / 16;
        return 1 + 5 * std::max(0.0, 1 - r2);
      },
      32, 24);
}

fs::path write_config(const fs::path& dir) {
  const fs::path p = dir / "fast.json";
  std::ofstream(p) << R"({"simulate": {"cell_mm": 0.05}})";
  return p;
}

// Issue 41: rest finishing behind a Ø4 ball with a Ø1 ball and pencil tracing with the Ø4, where
// the dome meets the block's top (a concave crease); the chain simulated: the rest program leaves
// less of the Ø4's rest than it found, and says how much of its feed path cut air.
TEST(CliFinish, RestAndPencilProgramsAreWrittenAcceptedAndScoredInTheChain) {
  const fs::path d = fresh_dir("finish_rest");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  const auto r = run_millnet(
      "finish --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
          "' --strategy 2 --tool ball:4 --stepover 0.3 --rest-tool ball:1 --pencil --pencil-offsets 2 --out out",
      d);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path out = d / "out";
  for (const char* f : {"dome.rest.nc", "dome.rest.json", "dome.rest.png", "dome.pencil.nc", "dome.pencil.json"})
    ASSERT_TRUE(fs::exists(out / f)) << f;
  const auto j = nlohmann::json::parse(slurp(out / "dome.rest.json"));
  for (const char* key : {"regions", "rest_axis_area_mm2", "max_rest_mm", "rest_top_z", "path_length_mm", "lifts"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["reference_tool"], "ball D4");
  const auto pj = nlohmann::json::parse(slurp(out / "dome.pencil.json"));
  EXPECT_EQ(pj["offsets_each_side"], 2);
  EXPECT_EQ(pj["offset_spacing_mm"], 0.3);
  EXPECT_NE(slurp(out / "dome.pencil.nc").find("2 offset passes each side"), std::string::npos);
  EXPECT_GE(j["regions"].get<int>(), 1);
  EXPECT_NE(slurp(out / "dome.rest.nc").find("(rest finishing behind ball D4"), std::string::npos);
  // The rest tool runs at its own cutting data (fz·z·n of a Ø1, not the Ø4's feed).
  const auto max_feed = [](const std::string& text) {
    double f = 0;
    for (std::size_t at = text.find('F'); at != std::string::npos; at = text.find('F', at + 1))
      if (at + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[at + 1])))
        f = std::max(f, std::stod(text.substr(at + 1)));
    return f;
  };
  const double rest_feed = max_feed(slurp(out / "dome.rest.nc")), finish_feed = max_feed(slurp(out / "dome.s2.nc"));
  EXPECT_GT(rest_feed, 0);
  EXPECT_LT(rest_feed, 0.75 * finish_feed) << rest_feed << " vs " << finish_feed;
  if (fs::exists("/usr/bin/rs274")) {
    EXPECT_TRUE(linuxcnc_accepts((out / "dome.rest.nc").string()));
    EXPECT_TRUE(linuxcnc_accepts((out / "dome.pencil.nc").string()));
  }
  const auto s = run_millnet("simulate --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --gcode out/dome.s2.nc --tool ball:4 --gcode out/dome.rest.nc --tool ball:1 "
                                 "--stock design --out sim",
                             d);
  ASSERT_EQ(s.code, 0) << s.err;
  const auto sim = nlohmann::json::parse(slurp(d / "sim" / "dome.sim.json"));
  const auto& rest = sim["programs"][1];
  EXPECT_EQ(rest["rest_reference_tool"], "ball D4");
  EXPECT_GT(rest["rest_area_before_mm2"].get<double>(), 0);
  EXPECT_LT(rest["rest_area_after_mm2"].get<double>(), rest["rest_area_before_mm2"].get<double>());
  EXPECT_GE(rest["air_cut_share"].get<double>(), 0);
  EXPECT_LE(rest["air_cut_share"].get<double>(), 1);
  EXPECT_LE(sim["max_gouge_mm"].get<double>(), 0.002);
  // The rest split by what each tool reaches: the rest tool leaves at most what it cannot reach
  // plus what it missed; the missed cells drawn.
  for (const char* key : {"rest_area_unreachable_mm2", "rest_area_missed_mm2", "over_threshold_before_mm2",
                          "over_threshold_after_mm2", "rest_threshold_mm"})
    EXPECT_TRUE(rest.contains(key)) << key;
  EXPECT_TRUE(fs::exists(d / "sim" / "dome.rest_missed.png"));
  EXPECT_LE(rest["rest_area_after_mm2"].get<double>(),
            rest["rest_area_unreachable_mm2"].get<double>() + rest["rest_area_missed_mm2"].get<double>() + 0.5);
}

// Rest from the stock (finish --rest-from): the finishing program's simulated stock saved, the rest
// program planned from it, scored in the chain; bad combinations and a missing file refused.
TEST(CliFinish, RestFromTheSimulatedStockIsPlannedFromWhatWasLeft) {
  const fs::path d = fresh_dir("finish_rest_stock");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  const std::string base = "--quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() + "' ";
  ASSERT_EQ(run_millnet("finish " + base + "--strategy 2 --tool ball:4 --stepover 0.3 --out out", d).code, 0);
  const auto s0 = run_millnet("simulate " + base +
                                  "--gcode out/dome.s2.nc --tool ball:4 --stock design --save-stock "
                                  "--no-preview --out sim0",
                              d);
  ASSERT_EQ(s0.code, 0) << s0.err;
  const auto r = run_millnet("finish " + base +
                                 "--strategy 2 --tool ball:4 --stepover 0.3 --rest-tool ball:1 "
                                 "--rest-from sim0 --out rest",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(d / "rest" / "dome.rest.json"));
  EXPECT_EQ(j["rest_from"], "the stock dome.zmap");
  EXPECT_GE(j["regions"].get<int>(), 1);
  EXPECT_NE(slurp(d / "rest" / "dome.rest.nc").find("(rest finishing behind the stock dome.zmap"), std::string::npos);
  if (fs::exists("/usr/bin/rs274")) EXPECT_TRUE(linuxcnc_accepts((d / "rest" / "dome.rest.nc").string()));
  const auto s = run_millnet("simulate " + base +
                                 "--gcode out/dome.s2.nc --tool ball:4 --gcode rest/dome.rest.nc "
                                 "--tool ball:1 --stock design --no-preview --out sim",
                             d);
  ASSERT_EQ(s.code, 0) << s.err;
  const auto sim = nlohmann::json::parse(slurp(d / "sim" / "dome.sim.json"));
  const auto& rest = sim["programs"][1];
  EXPECT_LT(rest["over_threshold_after_mm2"].get<double>(), rest["over_threshold_before_mm2"].get<double>());
  EXPECT_LE(sim["max_gouge_mm"].get<double>(), 0.002);
  EXPECT_EQ(rest["cutting_rapids"].get<int>(), 0);  // its links clear the stock, not only the design
  // Refused with one line each: both sources, no rest tool, a file that is not there.
  for (const std::string& bad :
       {std::string("--rest-tool ball:1 --rest-from sim0 --rest-reference ball:4"), std::string("--rest-from sim0"),
        std::string("--rest-tool ball:1 --rest-from nowhere.zmap")}) {
    const auto e = run_millnet("finish " + base + "--strategy 2 --tool ball:4 " + bad + " --out bad", d);
    EXPECT_NE(e.code, 0) << bad;
    EXPECT_NE(e.err.find("rest"), std::string::npos) << e.err;
  }
  EXPECT_NE(run_millnet("finish " + base +
                            "--strategy 2 --tool ball:4 --rest-tool ball:1 --rest-from nowhere.zmap "
                            "--out bad",
                        d)
                .err.find("nowhere.zmap"),
            std::string::npos);
}

TEST(CliFinish, AllStrategiesSimulatedWriteTheContractFilesAndLinuxCncAcceptsThem) {
  const fs::path d = fresh_dir("finish_all");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  const auto r = run_millnet("finish --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --strategy all --simulate --stepover 0.5 --step-down 0.5 --out out",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path out = d / "out";
  for (int k = 1; k <= 5; ++k) {
    const std::string base = "dome.s" + std::to_string(k);
    for (const char* ext : {".nc", ".metrics.json", ".png", ".ra.png"})
      ASSERT_TRUE(fs::exists(out / (base + ext))) << base << ext;
    const auto j = nlohmann::json::parse(slurp(out / (base + ".metrics.json")));
    for (const char* key :
         {"strategy", "path_length_mm", "time_feed_min", "time_kinematic_min", "lifts", "max_gouge_mm",
          "scallop_max_mm", "ra_median_um", "ra_p90_um", "ra_histogram", "uncut_area_mm2"})
      EXPECT_TRUE(j.contains(key)) << base << " lacks " << key;
    EXPECT_EQ(j["strategy"].get<int>(), k);
    EXPECT_LE(j["max_gouge_mm"].get<double>(), 0.002) << base << ": the program gouges the part";
    EXPECT_GE(j["time_kinematic_min"].get<double>(), j["time_feed_min"].get<double>() * 0.999);
    if (fs::exists("/usr/bin/rs274")) {
      EXPECT_TRUE(millnet::testing::linuxcnc_accepts((out / (base + ".nc")).string())) << base;
    }
    // The roughing frame: the part top (z 6) is at Z −1, the base (z 0) at Z −7.
    const std::string text = slurp(out / (base + ".nc"));
    const std::regex g1(R"(G1[^\n]*Z(-?[0-9.]+))");
    double zmax = -1e9, zmin = 1e9;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), g1); it != std::sregex_iterator(); ++it) {
      const double z = std::stod((*it)[1]);
      zmax = std::max(zmax, z), zmin = std::min(zmin, z);
    }
    EXPECT_LE(zmax, -1 + 1e-3) << base;
    EXPECT_GE(zmin, -7 - 1e-3) << base;
  }
  for (const char* f : {"dome.strategies.csv", "dome.strategies.md", "dome.strategies.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const std::string csv = slurp(out / "dome.strategies.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6) << csv;  // header + 5 ranked strategies
}

namespace {
/// strategies.csv as rows of named cells (header keys).
std::vector<std::map<std::string, std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> cells;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::string cell;
    bool quoted = false;
    for (const char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        row.push_back(std::exchange(cell, {}));
      else
        cell += c;
    }
    row.push_back(cell);
    cells.push_back(row);
  }
  std::vector<std::map<std::string, std::string>> rows;
  for (std::size_t r = 1; r < cells.size(); ++r) {
    std::map<std::string, std::string> m;
    for (std::size_t c = 0; c < cells[0].size() && c < cells[r].size(); ++c) m[cells[0][c]] = cells[r][c];
    rows.push_back(m);
  }
  return rows;
}
}  // namespace

// Issue 37 §2 as a user runs it: every strategy set up from one surface specification (here a
// 0.02 mm scallop: a Ø2 ball's passes w = 2√(2·0.02 − 0.02²) = 0.3980 mm apart), ranked by the time
// to meet it, each one's regret against the best; the paper's preset cuts the parameters as written.
TEST(CliFinish, StrategiesSetUpFromOneSpecificationAreRankedByTheTimeToMeetIt) {
  const fs::path d = fresh_dir("finish_spec");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  const auto r = run_millnet("finish --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --tool bn2-2f-carbide --strategy all --simulate --scallop 0.02 --out out",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const double w = 2 * std::sqrt(2 * 0.02 - 0.02 * 0.02);
  const double expect_stepover[] = {w * std::cos(std::numbers::pi / 6), w, w, 0.2 /* Z-level: no stepover of its own */,
                                    w};
  for (int k = 1; k <= 5; ++k) {
    const auto j = nlohmann::json::parse(slurp(d / "out" / ("dome.s" + std::to_string(k) + ".metrics.json")));
    EXPECT_EQ(j["params"]["from"], "spec") << k;
    EXPECT_NEAR(j["params"]["stepover_mm"].get<double>(), expect_stepover[k - 1], 1e-9) << k;
    if (k == 1 || k == 4) {
      EXPECT_NEAR(j["params"]["step_down_mm"].get<double>(), w / 2, 1e-9) << k;
    }
    ASSERT_TRUE(j.contains("spec")) << k;
    const double share = j["spec"]["share_in_spec"].get<double>();
    EXPECT_GE(share, 0.0);
    EXPECT_LE(share, 1.0);
  }
  EXPECT_NE(slurp(d / "out" / "dome.strategies.md").find("ranked by time_to_spec"), std::string::npos);
  const auto rows = csv_rows(slurp(d / "out" / "dome.strategies.csv"));
  ASSERT_EQ(rows.size(), 5u);
  // The best meets the spec (the dome's slopes are gentle enough for equidistant or scallop mode);
  // every strategy's regret is its time over the best's − 1; those that meet come first, by time
  // up to the 2 % near-tie rule.
  const auto& best = rows.front();
  ASSERT_EQ(best.at("meets_spec"), "yes");
  const double t_best = std::stod(best.at("time_kinematic_min"));
  bool missed = false;
  for (const auto& row : rows) {
    SCOPED_TRACE(row.at("strategy"));
    const double t = std::stod(row.at("time_kinematic_min"));
    EXPECT_NEAR(std::stod(row.at("regret")), t / t_best - 1, 2e-4);
    if (row.at("meets_spec") == "yes") {
      EXPECT_FALSE(missed) << "a strategy that meets the spec ranked after one that misses it";
      EXPECT_GE(t, t_best / 1.02);
    } else {
      missed = true;
    }
  }
  // The paper's fixed settings: the parameters as written, ranked by the quality aim.
  const fs::path paper = d / "paper.json";
  std::ofstream(paper) << R"({"finish": {"params_from": "fixed", "aim": "quality"}, "simulate": {"cell_mm": 0.05}})";
  const auto q = run_millnet("finish --quiet --config '" + paper.string() + "' --mesh '" + mesh.string() +
                                 "' --strategy all --simulate --out paper",
                             d);
  ASSERT_EQ(q.code, 0) << q.err;
  for (int k = 1; k <= 5; ++k) {
    const auto j = nlohmann::json::parse(slurp(d / "paper" / ("dome.s" + std::to_string(k) + ".metrics.json")));
    EXPECT_EQ(j["params"]["from"], "fixed");
    EXPECT_EQ(j["params"]["stepover_mm"].get<double>(), 0.2);
    EXPECT_EQ(j["params"]["step_down_mm"].get<double>(), 0.04);
  }
  EXPECT_NE(slurp(d / "paper" / "dome.strategies.md").find("ranked by quality"), std::string::npos);
  // A stepover on the command line is the one cut, and the run says so.
  const auto f = run_millnet(
      "finish --config '" + cfg.string() + "' --mesh '" + mesh.string() + "' --strategy 2 --stepover 0.5 --out flag",
      d);
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_NE(f.err.find("not derived from /finish/spec"), std::string::npos) << f.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(d / "flag" / "dome.s2.metrics.json"))["params"]["stepover_mm"].get<double>(),
            0.5);
}

TEST(CliFinish, BadInputGetsOneLineAndNoFiles) {
  const fs::path d = fresh_dir("finish_bad");
  const fs::path mesh = write_dome(d);
  const auto zero = run_millnet("finish --mesh '" + mesh.string() + "' --stepover 0 --out out", d);
  EXPECT_EQ(zero.code, 1);  // the flag is checked against /finish/stepover_mm's range
  EXPECT_NE(zero.err.find("stepover_mm"), std::string::npos) << zero.err;
  EXPECT_EQ(std::count(zero.err.begin(), zero.err.end(), '\n'), 1) << zero.err;
  const auto big = run_millnet("finish --mesh '" + mesh.string() + "' --strategy 2 --tool ball:40 --out out", d);
  EXPECT_EQ(big.code, 1);
  EXPECT_NE(big.err.find("larger than the machining boundary"), std::string::npos) << big.err;
  const auto tool = run_millnet("finish --mesh '" + mesh.string() + "' --tool sphere:2 --out out", d);
  EXPECT_EQ(tool.code, 1);
  EXPECT_NE(tool.err.find("ball:D"), std::string::npos) << tool.err;
  auto one_line = [](const auto& r, const std::string& what) {
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  one_line(run_millnet("finish --mesh '" + mesh.string() + "' --strategy 7 --out out", d), "--strategy");
  one_line(run_millnet("finish --mesh '" + mesh.string() + "' --strategy 4 --step-down 0 --out out", d),
           "step_down_mm");
  {  // a mesh with no face looking up (one vertical triangle)
    std::ofstream wall(d / "wall.stl");
    wall << "solid w\nfacet normal 1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 10 0\nvertex 0 5 10\nendloop\n"
            "endfacet\nendsolid w\n";
  }
  one_line(run_millnet("finish --mesh wall.stl --strategy all --simulate --out out", d), "no top surface");
  EXPECT_EQ(list_files(d / "out"), "");
}

TEST(CliSimulate, ReportsAGougeAtItsLineAndRejectsUnknownWords) {
  const fs::path d = fresh_dir("simulate");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  // Over the flat block (part z 1 → Z −6) a cut at Z −6.05 dips 0.05 mm into it, on line 5.
  std::ofstream(d / "dip.nc") << "G21 G90 G17 G94\nM3 S18000\nG0 Z5\nG0 X1 Y1\nG1 Z-6.05 F600\nG1 X2 F1900\n"
                                 "G0 Z5\nM5\nM30\n";
  const auto r = run_millnet("simulate --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --gcode dip.nc --tool ball:2 --stock design --out sim",
                             d);
  // issue 37 §1: a gouge the exact check confirms is a failure: exit 1, one line naming the
  // program, the depth, the line and the XY; the outputs are written and the program kept.
  ASSERT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("millnet simulate: error: dip.nc gouges the part: 0.05"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("first gouging line 5"), std::string::npos) << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex("X [12]\\.[0-9]{3} Y 1\\.000"))) << r.err;
  EXPECT_TRUE(fs::exists(d / "sim" / "dip.GOUGES.nc"));
  EXPECT_EQ(slurp(d / "sim" / "dip.GOUGES.nc"), slurp(d / "dip.nc"));
  const auto j = nlohmann::json::parse(slurp(d / "sim" / "dome.sim.json"));
  EXPECT_NEAR(j["max_gouge_mm"].get<double>(), 0.05, 1e-3);
  EXPECT_EQ(j["gouge_line"].get<int>(), 5);
  EXPECT_EQ(j["zmap_gouge_artefacts"].get<int>(), 0);
  EXPECT_TRUE(fs::exists(d / "sim" / "dome.ra.png"));
  EXPECT_TRUE(fs::exists(d / "sim" / "dome.deviation.png"));

  std::ofstream(d / "g54.nc") << "G21 G90\nG55\nG0 Z5\nM30\n";  // a second work offset: not read
  const auto bad = run_millnet("simulate --mesh '" + mesh.string() + "' --gcode g54.nc --tool ball:2 --out sim2", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("g54.nc:2"), std::string::npos) << bad.err;
  EXPECT_EQ(list_files(d / "sim2"), "");
}

// issue 36: the cutter had two owners; `finish --tool bull:4:2` exited 0 and `simulate --tool
// bull:4:2` on its program exited 1. One check now: both accept it (it is the Ø4 ball).
TEST(CliSimulate, ABullWithItsRadiusAsCornerIsAcceptedByFinishAndBySimulate) {
  const fs::path d = fresh_dir("simulate_bull_r_eq_R");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  const auto f = run_millnet("finish --quiet --no-preview --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --strategy 2 --stepover 1 --tool bull:4:2 --out fin",
                             d);
  ASSERT_EQ(f.code, 0) << f.err;
  const auto s = run_millnet("simulate --quiet --no-preview --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                 "' --gcode fin/dome.s2.nc --tool bull:4:2 --stock design --out sim",
                             d);
  ASSERT_EQ(s.code, 0) << s.err;
  const auto bad = run_millnet("simulate --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() +
                                   "' --gcode fin/dome.s2.nc --tool bull:4:2.5 --stock design --out sim2",
                               d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("corner radius <= diameter/2 = 2, got 2.5"), std::string::npos) << bad.err;
}

TEST(CliSimulate, AStockSavedByOneRunContinuesInTheNextAsIfItWereOneRun) {
  const fs::path d = fresh_dir("simulate_stock");
  const fs::path mesh = write_dome(d), cfg = write_config(d);
  // A "roughing" pass with a flat mill at Z −2.5 over the dome, then a ball pass lower down.
  std::ofstream(d / "a.nc") << "G21 G90 G17 G94\nM3 S9000\nG0 Z5\nG0 X-2 Y3\nG1 Z-2.5 F300\nG1 X18 F1500\n"
                               "G1 Y9\nG1 X-2\nG0 Z5\nM5\nM30\n";
  std::ofstream(d / "b.nc") << "G21 G90 G17 G94\nM3 S18000\nG0 Z5\nG0 X-2 Y6\nG1 Z-6 F600\nG1 X18 F1900\n"
                               "G0 Z5\nM5\nM30\n";
  const std::string base = "simulate --quiet --config '" + cfg.string() + "' --mesh '" + mesh.string() + "' ";
  const auto both =
      run_millnet(base + "--gcode a.nc --gcode b.nc --tool flat:6 --tool ball:2 --save-stock --out one", d);
  // Both programs cut through the dome (a real gouge, confirmed exactly): exit 1, outputs written.
  ASSERT_EQ(both.code, 1) << both.err;
  const auto first = run_millnet(base + "--gcode a.nc --tool flat:6 --save-stock --out s1", d);
  ASSERT_EQ(first.code, 1) << first.err;
  ASSERT_TRUE(fs::exists(d / "s1" / "dome.zmap"));
  const auto second = run_millnet(base + "--gcode b.nc --tool ball:2 --stock s1/dome.zmap --save-stock --out s2", d);
  ASSERT_EQ(second.code, 1) << second.err;
  // The machined heights are the same bytes; so are the figures that depend on heights only (Ra
  // may differ: a stock read back has no move history, so cells that only the first program cut
  // take their Ra profile along Y).
  EXPECT_TRUE(slurp(d / "one" / "dome.zmap") == slurp(d / "s2" / "dome.zmap"));
  const auto j1 = nlohmann::json::parse(slurp(d / "one" / "dome.sim.json"));
  const auto j2 = nlohmann::json::parse(slurp(d / "s2" / "dome.sim.json"));
  // (the confirmed gouge needs the programs: the z-map's own figure is the heights' alone)
  for (const char* k : {"zmap_max_gouge_mm", "uncut_area_mm2"})
    EXPECT_EQ(j1[k].get<double>(), j2[k].get<double>()) << k;
  EXPECT_GT(j1["programs"][1]["max_depth_of_cut_mm"].get<double>(), 0.5);
  EXPECT_EQ(j1["programs"][1]["max_depth_of_cut_mm"], j2["programs"][0]["max_depth_of_cut_mm"]);

  // A stock of another grid, a truncated file, a text file: one line naming the file; nothing written.
  std::ofstream(d / "coarse.json") << R"({"simulate": {"cell_mm": 0.1}})";
  const auto grid = run_millnet("simulate --config coarse.json --mesh '" + mesh.string() +
                                    "' --gcode b.nc --tool ball:2 --stock s1/dome.zmap --out bad1",
                                d);
  EXPECT_EQ(grid.code, 1);
  EXPECT_NE(grid.err.find("dome.zmap"), std::string::npos) << grid.err;
  EXPECT_NE(grid.err.find("is not this part's"), std::string::npos) << grid.err;
  EXPECT_EQ(std::count(grid.err.begin(), grid.err.end(), '\n'), 1) << grid.err;
  const std::string bytes = slurp(d / "s1" / "dome.zmap");
  std::ofstream(d / "cut.zmap", std::ios::binary) << bytes.substr(0, bytes.size() - 5);
  const auto cut = run_millnet(base + "--gcode b.nc --tool ball:2 --stock cut.zmap --out bad2", d);
  EXPECT_EQ(cut.code, 1);
  EXPECT_NE(cut.err.find("cut.zmap"), std::string::npos) << cut.err;
  EXPECT_NE(cut.err.find("bytes of heights"), std::string::npos) << cut.err;
  const auto text = run_millnet(base + "--gcode b.nc --tool ball:2 --stock a.nc --out bad3", d);
  EXPECT_EQ(text.code, 1);
  EXPECT_NE(text.err.find("not a millnet z-map"), std::string::npos) << text.err;
  for (const char* o : {"bad1", "bad2", "bad3"}) EXPECT_EQ(list_files(d / o), "") << o;
}

// /simulate/cells_per_pass: the z-map cell is the passes' spacing for the specification on the
// cutter (w = 2√(2Rh − h²) for a ball, h the default 0.005 mm scallop), or the fixed stepover, over
// the cells asked per pass — at most R/4 — and in a chain the finest cutter's. Hand-computed cells.
TEST(CliSimulate, ACellPerPassFollowsTheSpecificationAndTheFinestCutter) {
  const fs::path d = fresh_dir("simulate_cells_per_pass");
  const fs::path mesh = write_dome(d);
  std::ofstream(d / "air.nc") << "G21 G90 G17 G94\nM3 S18000\nG0 Z5\nG0 X-2 Y6\nG1 Z3 F600\nG1 X18 F1900\n"
                                 "G0 Z5\nM5\nM30\n";
  std::ofstream(d / "per5.json") << R"({"simulate": {"cells_per_pass": 5}})";
  std::ofstream(d / "fixed.json") << R"({"finish": {"params_from": "fixed", "stepover_mm": 0.2},
                                         "simulate": {"cells_per_pass": 4}})";
  std::ofstream(d / "fine.json") << R"({"simulate": {"cells_per_pass": 1000}})";
  std::ofstream(d / "none.json") << R"({})";
  const auto cell = [&](const std::string& cfg, const std::string& tools, const std::string& out) {
    const auto r = run_millnet("simulate --quiet --config " + cfg + " --mesh '" + mesh.string() + "' " + tools +
                                   " --stock design --out " + out,
                               d);
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(slurp(d / out / "dome.sim.json"))["cell_mm"].get<double>();
  };
  const auto w = [](double R, double h) { return 2 * std::sqrt(2 * R * h - h * h); };
  EXPECT_NEAR(cell("per5.json", "--gcode air.nc --tool ball:2", "b2"), w(1, 0.005) / 5, 1e-12);  // 0.03995
  EXPECT_NEAR(cell("per5.json", "--gcode air.nc --tool ball:6", "b6"), w(3, 0.005) / 5, 1e-12);  // 0.06925
  EXPECT_NEAR(cell("per5.json", "--gcode air.nc --tool flat:1", "f1"), 0.125, 1e-12);            // 1 / 5 over R/4
  EXPECT_NEAR(cell("fixed.json", "--gcode air.nc --tool ball:2", "fx"), 0.05, 1e-12);
  EXPECT_NEAR(cell("per5.json", "--gcode air.nc --gcode air.nc --tool flat:6 --tool ball:2", "chain"), w(1, 0.005) / 5,
              1e-12);
  EXPECT_NEAR(cell("none.json", "--gcode air.nc --tool ball:2", "none"), 0.025, 1e-12);  // /simulate/cell_mm
  // Too fine for the memory limit: refused before anything is allocated, naming the key that sets it.
  const auto fine = run_millnet("simulate --config fine.json --mesh '" + mesh.string() +
                                    "' --gcode air.nc --tool ball:2 --stock design --out fine",
                                d);
  EXPECT_EQ(fine.code, 1);
  EXPECT_NE(fine.err.find("/simulate/cells_per_pass "), std::string::npos) << fine.err;
  EXPECT_NE(fine.err.find(" fits"), std::string::npos) << fine.err;
  EXPECT_EQ(list_files(d / "fine"), "");
}

// A cell from the passes' spacing is coarser (0.04 mm for the Ø2 here) and finds the rest material by
// hand: a 10 × 8 mm pocket 4 mm deep, whose floor band within the ball's radius of the walls the Ø2
// cannot reach, 10 × 8 − 8 × 6 = 32 mm² (a little less: the walls' feet slope over a quarter mm).
TEST(CliFinish, ACoarserCellPerPassFindsTheSameRestMaterial) {
  const fs::path d = fresh_dir("finish_cells_per_pass_rest");
  const fs::path mesh = write_solid(
      d, "pocket", [](double x, double y) { return std::abs(x - 8) < 5 && std::abs(y - 6) < 4 ? 1.0 : 5.0; }, 128, 96);
  std::ofstream(d / "fine.json") << R"({"simulate": {"cell_mm": 0.025}})";
  std::ofstream(d / "per5.json") << R"({"simulate": {"cells_per_pass": 5}})";
  const auto figures = [&](const std::string& cfg, const std::string& out) {
    const auto r = run_millnet("finish --quiet --no-preview --config " + cfg + " --mesh '" + mesh.string() +
                                   "' --strategy 2 --simulate --tool ball:2 --out " + out,
                               d);
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(slurp(d / out / "pocket.s2.metrics.json"));
  };
  const auto fine = figures("fine.json", "fine"), coarse = figures("per5.json", "coarse");
  const double rest = fine["rest_area_mm2"].get<double>();
  EXPECT_NEAR(rest, 31, 1.0);
  EXPECT_NEAR(coarse["rest_area_mm2"].get<double>(), rest, 0.02 * rest);
  // Judged: the footprint less the rest band; in spec all but the walls' steep feet.
  for (const auto* j : {&fine, &coarse}) {
    EXPECT_NEAR((*j)["spec"]["judged_area_mm2"].get<double>(), 16 * 12 - 32, 1.0);
    EXPECT_GT((*j)["spec"]["share_in_spec"].get<double>(), 0.98);
  }
}

// `simulate --moves`: every move as machined, one row each, in the program's own work frame (here
// the stock's centre): a cut 0.5 mm into the flat block over the dome (its top is at Z −1), the
// same 12 mm back over what it cut (air), as the file's lines state them.
TEST(CliSimulate, EveryMoveIsListedWithWhatItCutInTheProgramsOwnFrame) {
  const fs::path d = fresh_dir("simulate_moves");
  const fs::path mesh = write_dome(d);
  std::ofstream(d / "cfg.json") << R"({"simulate": {"cell_mm": 0.05}, "machine": {"work_origin": "stock_centre"}})";
  const std::string program =
      "G21 G90 G17 G94\nM3 S18000\nG0 Z5\nG0 X-6 Y0.5\nG1 Z-0.5 F600\nG1 X6 F1900\n"
      "G1 X-6\nG0 Z5\nM5\nM30\n";
  std::ofstream(d / "pass.nc") << program;
  const auto r = run_millnet("simulate --quiet --no-preview --config cfg.json --mesh '" + mesh.string() +
                                 "' --gcode pass.nc --tool ball:2 --moves --out sim",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(d / "sim" / "dome.sim.json"));
  EXPECT_EQ(j["moves_csv"].get<std::string>(), (fs::path("sim") / "dome.moves.csv").string());
  std::istringstream csv(slurp(d / "sim" / "dome.moves.csv"));
  std::string row;
  std::getline(csv, row);
  EXPECT_EQ(row, "program,line,motion,x,y,z,length_mm,cut_mm,kind");
  std::vector<std::string> lines{""};
  for (std::istringstream text(program); std::getline(text, row);) lines.push_back(row);
  std::vector<std::pair<int, std::string>> kinds;
  double air = 0;
  while (std::getline(csv, row)) {
    std::vector<std::string> f;
    for (std::istringstream cells(row); std::getline(cells, row, ',');) f.push_back(row);
    ASSERT_EQ(f.size(), 9U);
    EXPECT_EQ(f[0], "pass.nc");
    const int line = std::stoi(f[1]);
    kinds.emplace_back(line, f[8]);
    if (f[8] == "air") air += std::stod(f[6]);
    // The row's end point is the file's: every axis its line states, as written.
    const std::string& g = lines.at(static_cast<std::size_t>(line));
    EXPECT_EQ(g.rfind(f[2], 0), 0U) << g;
    for (const auto& [axis, value] : {std::pair{'X', f[3]}, {'Y', f[4]}, {'Z', f[5]}})
      if (const auto at = g.find(axis); at != std::string::npos)
        EXPECT_NEAR(std::stod(g.substr(at + 1)), std::stod(value), 1e-9) << g << " | " << row;
  }
  const std::vector<std::pair<int, std::string>> expected{{3, "rapid"}, {4, "rapid"}, {5, "cut"},
                                                          {6, "cut"},   {7, "air"},   {8, "rapid"}};
  EXPECT_EQ(kinds, expected);
  EXPECT_NEAR(air, 12, 1e-9);
  EXPECT_NEAR(j["programs"][0]["air_feed_mm"].get<double>(), 12, 1e-9);
  EXPECT_NEAR(j["programs"][0]["feed_mm"].get<double>(), 5.5 + 12 + 12, 1e-9);
  // Without the flag no such file.
  ASSERT_EQ(run_millnet("simulate --quiet --no-preview --config cfg.json --mesh '" + mesh.string() +
                            "' --gcode pass.nc --tool ball:2 --out sim2",
                        d)
                .code,
            0);
  EXPECT_FALSE(fs::exists(d / "sim2" / "dome.moves.csv"));
}

TEST(CliTrain, ANetworkOnSimulatedScoresIsJudgedByRegretAndPredictsOnlyForItsAim) {
  const fs::path d = fresh_dir("train_scores");
  (void)write_dome(d);
  fs::copy_file(d / "dome.stl", d / "dome2.stl");
  std::ofstream(d / "cfg.json") << R"({"dataset": {"parts": [{"file": "dome.stl", "label": "simulate"},
                                                             {"file": "dome2.stl", "label": "simulate"}],
                                                   "raster_mm": 0.5,
                                                   "augment": {"angles_deg": [0, 10], "axes": ["x"], "flip": false}},
                                       "finish": {"stepover_mm": 0.5, "step_down_mm": 0.5},
                                       "simulate": {"cell_mm": 0.1}})";
  ASSERT_EQ(run_millnet("dataset --quiet --config cfg.json --out ds", d).code, 0);
  const auto t = run_millnet("train --quiet --config cfg.json --dataset ds/vectors.csv --out M", d);
  ASSERT_EQ(t.code, 0) << t.err;
  const auto rep = nlohmann::json::parse(slurp(d / "M" / "train_report.json"));
  ASSERT_TRUE(rep.contains("regret")) << rep.dump();
  const auto& r = rep["regret"];
  EXPECT_EQ(r["criterion"], "regret");
  EXPECT_EQ(r["outputs"], "scores");
  // The same mesh twice: leaving one out, the other's scores are the prediction, so the pick is right.
  EXPECT_EQ(r["leave_one_part_out"]["parts"], 2);
  EXPECT_EQ(r["leave_one_part_out"]["top1"], 1.0);
  EXPECT_EQ(r["leave_one_part_out"]["mean_regret"], 0.0);
  EXPECT_EQ(r["always_the_same_strategy"]["mean_regret"], 0.0);
  EXPECT_EQ(r["parts"].size(), 2u);
  const auto model = nlohmann::json::parse(slurp(d / "M" / "model.json"));
  EXPECT_EQ(model["target"]["aim"], "time_to_spec");
  EXPECT_EQ(model["target"]["spec"]["scallop_mm"], 0.005);
  EXPECT_TRUE(fs::exists(d / "M" / "loo_regret.png"));
  EXPECT_NE(slurp(d / "M" / "loo_curve.csv").find(",mean_regret\n"), std::string::npos);

  const auto p = run_millnet("predict --quiet --model M --config cfg.json --out P dome.stl", d);
  ASSERT_EQ(p.code, 0) << p.err;
  const auto pred = nlohmann::json::parse(slurp(d / "P" / "predictions.json"));
  const auto& part = pred["parts"][0];
  const double conf = part["confidence"].get<double>();
  EXPECT_GE(conf, 0.0);
  EXPECT_LE(conf, 1.0);
  EXPECT_EQ(part["regret_risk"], 0.0);  // both neighbours say the pick is their best
  EXPECT_EQ(part["ranking"][0]["expected_regret"], 0.0);
  // The spare slots 6..8 were never machined: no expected regret (not 100 %); the strategies have one.
  int spares = 0;
  for (const auto& entry : part["ranking"]) {
    const bool spare = entry["strategy"].get<std::string>().rfind("spare ", 0) == 0;
    spares += spare ? 1 : 0;
    EXPECT_EQ(entry["expected_regret"].is_null(), spare) << entry.dump();
  }
  EXPECT_EQ(spares, 3);

  // One model per aim: a config asking for another aim or specification is refused, naming both.
  std::ofstream(d / "quality.json") << R"({"finish": {"aim": "quality"}})";
  const auto q = run_millnet("predict --model M --config quality.json --out Q dome.stl", d);
  EXPECT_EQ(q.code, 1);
  EXPECT_NE(q.err.find("trained for aim time_to_spec"), std::string::npos) << q.err;
  EXPECT_NE(q.err.find("asks for aim quality"), std::string::npos) << q.err;
  EXPECT_FALSE(fs::exists(d / "Q" / "predictions.json"));
  std::ofstream(d / "spec.json") << R"({"finish": {"spec": {"scallop_mm": 0.01}}})";
  const auto sp = run_millnet("predict --model M --config spec.json --out S dome.stl", d);
  EXPECT_EQ(sp.code, 1);
  EXPECT_NE(sp.err.find("\"scallop_mm\":0.01"), std::string::npos) << sp.err;
}

TEST(CliDataset, APartLabelledBySimulationGetsTheStrategyItsSimulationRanksFirst) {
  const fs::path d = fresh_dir("dataset_simulate");
  const fs::path mesh = write_dome(d);
  fs::copy_file(mesh, d / "dome2.stl");
  std::ofstream(d / "cfg.json") << R"({"dataset": {"parts": [{"file": "dome.stl", "label": "simulate"},
                                                             {"file": "dome2.stl", "label": 2}],
                                                   "raster_mm": 0.5,
                                                   "augment": {"angles_deg": [0, 10], "axes": ["x"], "flip": false}},
                                       "finish": {"stepover_mm": 0.5, "step_down_mm": 0.5},
                                       "simulate": {"cell_mm": 0.05}})";
  const auto r = run_millnet("dataset --quiet --config cfg.json --agreement --out ds", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto m = nlohmann::json::parse(slurp(d / "ds" / "manifest.json"));
  ASSERT_TRUE(m.contains("labelling")) << m.dump();
  const auto& parts = m["labelling"]["parts"];
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(m["config"]["parts"][0]["label"], "simulate");
  EXPECT_EQ(m["config"]["parts"][1]["label"], 2);
  for (const auto& p : parts) {
    ASSERT_EQ(p["strategies"].size(), 5u);
    int best = 0;
    for (const auto& st : p["strategies"])
      if (st["rank"] == 1) best = st["strategy"].get<int>();
    EXPECT_EQ(p["simulated_best"].get<int>(), best);
  }
  // Labelling writes no program, picture or page (issue 36): the figures are in the manifest.
  EXPECT_FALSE(fs::exists(d / "ds" / "labelling"));
  // The simulated part's rows carry its simulated best (the same mesh: the same best as dome2's
  // simulation), the other part keeps its label 2.
  const int best = parts[0]["simulated_best"].get<int>();
  EXPECT_EQ(parts[1]["simulated_best"].get<int>(), best);
  const std::string csv = slurp(d / "ds" / "vectors.csv");
  EXPECT_NE(csv.find("\ndome#1,dome," + std::to_string(best) + ","), std::string::npos) << csv.substr(0, 200);
  EXPECT_NE(csv.find("\ndome2#1,dome2,2,"), std::string::npos);
  // The agreement counts only the recipe-labelled part.
  const auto& ag = m["labelling"]["agreement"];
  ASSERT_EQ(ag.size(), 1u);
  EXPECT_EQ(ag[0]["label"], 2);
  EXPECT_EQ(ag[0]["parts"], 1);
  EXPECT_EQ(ag[0]["agree"], best == 2 ? 1 : 0);
  EXPECT_TRUE(fs::exists(d / "ds" / "agreement.md"));

  // Issue 39: the simulated part's outputs are its strategies' scores (the best 1, the others its
  // time / theirs or 0), kept in ds/labels.json with the part file's hash.
  const auto labels = nlohmann::json::parse(slurp(d / "ds" / "labels.json"));
  ASSERT_EQ(labels["parts"].size(), 2u);
  EXPECT_EQ(labels["aim"], "time_to_spec");
  const auto& dome = labels["parts"][0];
  EXPECT_EQ(dome["name"], "dome");
  EXPECT_EQ(dome["best"].get<int>(), best);
  double t_best = 0;
  for (const auto& st : dome["strategies"])
    if (st["rank"] == 1) t_best = st["time_kinematic_min"].get<double>();
  for (const auto& st : dome["strategies"]) {
    const double score = st["score"].get<double>();
    if (st["rank"] == 1) {
      EXPECT_EQ(score, 1.0);
    } else if (st["meets_spec"].get<bool>() && st["max_gouge_mm"].get<double>() <= 0.002) {
      EXPECT_NEAR(score, std::min(t_best / st["time_kinematic_min"].get<double>(), 1 - 1e-6), 1e-12);
    } else {
      EXPECT_EQ(score, 0.0);
    }
  }
  // The cache: a recipe naming these labels simulates nothing again (the line says so) and gives the
  // same table, byte for byte; a label edited in the file is what the table then carries.
  std::ofstream(d / "cached.json") << R"({"dataset": {"parts": [{"file": "dome.stl", "label": "simulate"},
                                                                {"file": "dome2.stl", "label": 2}],
                                                      "labels": "ds/labels.json", "raster_mm": 0.5,
                                                      "augment": {"angles_deg": [0, 10], "axes": ["x"], "flip": false}},
                                          "finish": {"stepover_mm": 0.5, "step_down_mm": 0.5},
                                          "simulate": {"cell_mm": 0.05}})";
  const auto again = run_millnet("dataset --config cached.json --out ds_cached", d);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("1 of 1 parts from"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(d / "ds_cached" / "vectors.csv"), csv);
  // --relabel recomputes the label: the same bytes (a label is a deterministic computation).
  const auto re = run_millnet("dataset --quiet --config cached.json --relabel --out ds_re", d);
  ASSERT_EQ(re.code, 0) << re.err;
  EXPECT_EQ(slurp(d / "ds_re" / "labels.json"), slurp(d / "ds_cached" / "labels.json"));
  std::string edited = slurp(d / "ds" / "labels.json");
  const std::size_t at = edited.find("\"ra_median_um\": ");
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, edited.find(',', at) - at, "\"ra_median_um\": 123.5");
  std::ofstream(d / "ds" / "labels.json") << edited;
  const auto stale = run_millnet("dataset --quiet --config cached.json --out ds_edited", d);
  ASSERT_EQ(stale.code, 0) << stale.err;
  const auto edited_labels = nlohmann::json::parse(slurp(d / "ds_edited" / "labels.json"));
  EXPECT_EQ(edited_labels["parts"][0]["strategies"][0]["ra_median_um"], 123.5);
  // A setting changed: the cache is not used (the line names why) and the part is simulated again.
  std::ofstream(d / "other.json") << R"({"dataset": {"parts": [{"file": "dome.stl", "label": "simulate"}],
                                                     "labels": "ds/labels.json", "raster_mm": 0.5,
                                                     "augment": {"angles_deg": [0], "axes": ["x"], "flip": false}},
                                         "finish": {"stepover_mm": 0.5, "step_down_mm": 0.5},
                                         "simulate": {"cell_mm": 0.1}})";
  const auto other = run_millnet("dataset --config other.json --out ds_other", d);
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_NE(other.err.find("computed with other settings"), std::string::npos) << other.err;

  std::ofstream(d / "bad.json") << R"({"dataset": {"parts": [{"file": "dome.stl", "label": "simulated"}]}})";
  const auto bad = run_millnet("dataset --config bad.json --out ds2", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("/dataset/parts/0/label"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("[\"simulate\"]"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace millnet::testing
