// End-to-end tests of `millnet pocket` and `millnet compare` through the built executable: the
// command-line contract (files, metrics keys, exit codes, one-line errors), and the written G-code
// re-read by the independent replay (tests/testing/gcode_replay), which shares no code with the
// pocket module: gouge-free within 0.01 mm, floor Z, step-down levels, lengths agreeing with the
// metrics, determinism, and the precedence flags > config > pocket file keys.
#include "cli_runner.hpp"
#include "testing/gcode_replay.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include <sys/resource.h>

namespace {

namespace fs = std::filesystem;
using millnet::testing::CliResult;
using millnet::testing::fresh_dir;
using millnet::testing::list_files;
using millnet::testing::ReplayLoop;
using millnet::testing::ReplayPocket;
using millnet::testing::ReplayResult;
using millnet::testing::run_millnet;
using millnet::testing::slurp;
using nlohmann::json;

/// The gouge tolerance of the contract (issue 3): the tool disk may reach at most 0.01 mm into a wall.
constexpr double kGougeTolMm = 0.01;
/// The G-code carries 4 decimals: summed over thousands of segments the replay's lengths drift by
/// ≤ ~1e-6 relative from the planner's exact figures (same tolerance as tests/pocket).
double length_tol(double len) { return 1e-3 + 2e-6 * len; }
constexpr double kRapidTolMm = 1e-2;
constexpr double kPi = 3.14159265358979323846;

std::string bench(const std::string& name) {
  return std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json";
}

ReplayLoop loop_of(const json& a) {
  ReplayLoop l;
  for (const auto& v : a)
    l.push_back({v.at(0).get<double>(), v.at(1).get<double>(), v.size() > 2 ? v.at(2).get<double>() : 0.0});
  return l;
}

/// The pocket as the test reads it itself (nlohmann, not pocket_io): the replay's walls.
ReplayPocket replay_pocket_of(const fs::path& pocket_json) {
  const json j = json::parse(slurp(pocket_json));
  ReplayPocket p;
  p.boundary = loop_of(j.at("boundary"));
  if (j.contains("islands"))
    for (const auto& i : j["islands"]) p.islands.push_back(loop_of(i));
  return p;
}

struct PocketRun {
  CliResult r;
  fs::path out;
  json metrics;
  std::string nc;
};

/// `millnet pocket --pocket FILE <flags> --quiet --out <dir>/o` (cwd = dir).
PocketRun run_pocket(const std::string& pocket, const std::string& flags, const fs::path& dir) {
  PocketRun pr;
  pr.out = dir / "o";
  pr.r = run_millnet("pocket --pocket '" + pocket + "' " + flags + " --quiet --out o", dir);
  const std::string stem = fs::path(pocket).stem().string();
  if (fs::exists(pr.out / (stem + ".metrics.json"))) pr.metrics = json::parse(slurp(pr.out / (stem + ".metrics.json")));
  if (fs::exists(pr.out / (stem + ".nc"))) pr.nc = slurp(pr.out / (stem + ".nc"));
  return pr;
}

double num(const json& m, const char* key) {
  if (!m.contains(key) || !m[key].is_number()) {
    ADD_FAILURE() << "metrics key '" << key << "' missing or not a number";
    return std::nan("");
  }
  return m[key].get<double>();
}

/// Checks everything the contract promises about one successful run; returns the replay.
ReplayResult check_run(const PocketRun& pr, const std::string& stem, const ReplayPocket& pocket, double tool_diameter,
                       double depth, bool predrill) {
  EXPECT_EQ(pr.r.code, 0) << pr.r.err;
  for (const char* ext : {".nc", ".metrics.json", ".points.csv", ".png"})
    EXPECT_TRUE(fs::exists(pr.out / (stem + ext))) << stem << ext << "\n" << list_files(pr.out);
  for (const char* k : {"tool_points", "cut_length_mm", "rapid_length_mm", "retractions", "plunges", "predrill_points",
                        "planning_time_s", "time_adjusted_min", "time_constant_min"})
    EXPECT_TRUE(pr.metrics.contains(k) && pr.metrics[k].is_number()) << "metrics key " << k;
  if (pr.r.code != 0 || pr.nc.empty()) return {};
  // Tool points file: header x,y and one row per tool point.
  {
    std::istringstream in(slurp(pr.out / (stem + ".points.csv")));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "x,y");
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      ++rows;
      EXPECT_EQ(std::count(line.begin(), line.end(), ','), 1) << line;
    }
    EXPECT_EQ(static_cast<double>(rows), num(pr.metrics, "tool_points"));
    // Zigzag has passes, not a grid of tool points: its file may be just the header.
    if (pr.metrics.value("planner", "") == "som") {
      EXPECT_GT(rows, 10u);
    }
  }
  // The picture is a real PNG.
  const cv::Mat img = cv::imread((pr.out / (stem + ".png")).string(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(img.empty());
  EXPECT_GE(img.cols, 200);
  // Independent re-read of the G-code.
  const double safe_z = pr.metrics["parameters"]["safe_z"].get<double>();
  ReplayResult rep = millnet::testing::replay_gcode(pr.nc, safe_z);
  millnet::testing::check_gouge(rep, pocket, tool_diameter / 2, kGougeTolMm, 0.05);
  EXPECT_EQ(rep.violations, 0) << stem << ": " << rep.first_violation;
  EXPECT_LT(rep.worst_mm, kGougeTolMm);
  EXPECT_GT(rep.samples, 1000);
  EXPECT_NEAR(rep.min_z, -depth, 1e-9);
  EXPECT_TRUE(rep.uses_feed_everywhere);
  // The metrics agree with the replay's own figures. Drilling is pure Z (no cut length); the replay
  // cannot tell a drilled hole from a milling entry, so each hole adds one plunge and one retraction.
  EXPECT_NEAR(num(pr.metrics, "cut_length_mm"), rep.cut_length, length_tol(rep.cut_length));
  EXPECT_NEAR(num(pr.metrics, "rapid_length_mm"), rep.rapid_length, kRapidTolMm);
  const double holes = predrill ? num(pr.metrics, "predrill_points") : 0.0;
  if (!predrill) {
    EXPECT_EQ(num(pr.metrics, "predrill_points"), 0);
  }
  // Entries counted here: after a rapid, the first descending feed move that ends below Z 0 (a
  // straight plunge, a drilled hole, the turn of a helix or the leg of a ramp that passes Z 0, or
  // the plunge from a rapid down into the previous level's cleared area). Every entry but the
  // first follows a retraction.
  int entries = 0;
  bool armed = false;
  for (const auto& m : rep.moves) {
    if (m.g == 0) {
      armed = true;
    } else if (armed && m.to[2] < m.from[2] - 1e-12 && m.to[2] < 0) {
      ++entries;
      armed = false;
    }
  }
  EXPECT_EQ(static_cast<double>(entries), num(pr.metrics, "plunges") + holes);
  EXPECT_EQ(static_cast<double>(entries - 1), num(pr.metrics, "retractions") + holes);
  if (predrill) {  // the replay's own counts see straight plunges only
    EXPECT_EQ(static_cast<double>(rep.retractions), num(pr.metrics, "retractions") + holes);
    EXPECT_EQ(static_cast<double>(rep.plunges), num(pr.metrics, "plunges") + holes);
  }
  EXPECT_GE(num(pr.metrics, "time_constant_min"),
            0.9 * rep.cut_length / pr.metrics["parameters"]["feed_max"].get<double>());
  EXPECT_GT(num(pr.metrics, "time_adjusted_min"), 0);
  return rep;
}

std::size_t lines_of(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

}  // namespace

// Every planner variant on every bench pocket: gouge-free by the independent replay, floor at
// −depth, metrics = replay; SOM with linking: no retraction and a tour within 5 % of the grid bound.
class CliBenchPocket : public ::testing::TestWithParam<const char*> {};

TEST_P(CliBenchPocket, EveryPlannerIsGougeFreeAndAgreesWithReplay) {
  const std::string name = GetParam();
  const ReplayPocket pocket = replay_pocket_of(bench(name));
  struct Variant {
    const char* tag;
    std::string flags;
    bool predrill;
  };
  // The seed's SOM planner (grid points only, sharp corners: /pocket/som/walls and
  // /pocket/smoothing/blend_corners off, as in the 1995 preset) with and without the contour pass,
  // and today's (wall rings in the tour, corner arcs: it cuts the walls itself, issue 11).
  const std::string seed = "--config '" + std::string(MILLNET_SOURCE_DIR) + "/configs/presets/shin-suh-1995.json' ";
  const Variant variants[] = {
      {"som-seed", seed + "--planner som --no-contour", true},
      {"som-contour", seed + "--planner som --contour", true},
      {"som", "--planner som --no-contour", true},
      {"som-walls-contour", "--planner som --contour", true},
      {"som-helix", "--planner som --entry helix", false},
      {"zz-t", "--planner zigzag --partition t --angle auto --no-contour", true},
      {"zz-i-contour", "--planner zigzag --partition i --angle auto --contour", true},
      {"zz-i-helix", "--planner zigzag --partition i --angle auto --entry helix --contour", false},
      {"offset-helix", "--planner offset --entry helix", false},
      {"offset-predrill", "--planner offset", true},
      {"adaptive-helix", "--planner adaptive --entry helix", false},
  };
  double som_cut = 0, som_contour_cut = 0, som_walls_cut = 0;
  for (const Variant& v : variants) {
    SCOPED_TRACE(name + " " + v.tag);
    const PocketRun pr = run_pocket(bench(name), v.flags, fresh_dir("cli_pocket_" + name + "_" + v.tag));
    ASSERT_EQ(pr.r.code, 0) << pr.r.err;
    const std::string tag = v.tag;
    EXPECT_EQ(pr.metrics.value("planner", "").substr(0, 3), tag.substr(0, 2) == "zz"    ? "zig"
                                                            : tag.substr(0, 3) == "off" ? "off"
                                                            : tag.substr(0, 3) == "ada" ? "ada"
                                                                                        : "som");
    // The bench files say Ø10, stepover 5, depth 5; the default step-down 5 ⇒ one level.
    EXPECT_EQ(pr.metrics["parameters"]["tool_diameter"].get<double>(), 10);
    const ReplayResult rep = check_run(pr, name, pocket, 10, 5, v.predrill);
    EXPECT_EQ(rep.cut_length_by_z.size(), 1u);
    if (std::string(v.tag) == "som-seed") {
      // Issue 3's goals with linking on: the reachable region of each bench pocket is connected.
      EXPECT_EQ(num(pr.metrics, "retractions"), 0);
      const double n = num(pr.metrics, "tool_points");
      EXPECT_LE(num(pr.metrics, "cut_length_mm"), 1.05 * (n - 1) * 5.0);
      // A tour through N grid points at spacing 5 cannot be shorter than (N − 1)·5.
      EXPECT_GE(rep.cut_length, (n - 1) * 5.0 - 1e-6);
      som_cut = rep.cut_length;
    }
    if (std::string(v.tag) == "som-contour") som_contour_cut = rep.cut_length;
    if (tag == "som" || tag == "som-walls-contour") {
      // Issue 11: the SOM alone clears the pocket (walls included, no contour pass added either
      // way), one reachable region ⇒ no retraction.
      EXPECT_EQ(num(pr.metrics, "retractions"), 0);
      EXPECT_LE(num(pr.metrics, "uncut_area_mm2"), 2.0);
      EXPECT_GT(num(pr.metrics, "corner_arcs"), 0);
      if (tag == "som")
        som_walls_cut = rep.cut_length;
      else
        EXPECT_NEAR(rep.cut_length, som_walls_cut, 1e-6);
    }
    if (tag.substr(0, 6) == "offset") {
      // Issue 11: walls included, one reachable region ⇒ no retraction, and nothing reachable uncut.
      EXPECT_EQ(num(pr.metrics, "retractions"), 0);
      if (!v.predrill) {
        EXPECT_EQ(rep.retractions, 0);  // (the pre-drilling operation lifts once)
      }
      EXPECT_LE(num(pr.metrics, "uncut_area_mm2"), 2.0);
      EXPECT_GT(num(pr.metrics, "time_kinematic_min"), num(pr.metrics, "cut_length_mm") / 1500 / 10);
    }
    if (tag.substr(0, 8) == "adaptive") {
      // Issue 11: one reachable region ⇒ no retraction, nothing reachable uncut, one helix entry.
      EXPECT_EQ(num(pr.metrics, "retractions"), 0);
      EXPECT_EQ(rep.retractions, 0);
      EXPECT_LE(num(pr.metrics, "uncut_area_mm2"), 2.0);
      EXPECT_NE(pr.nc.find("helix entry"), std::string::npos);
      if (fs::exists("/usr/bin/rs274")) {  // LinuxCNC's own interpreter accepts the program
        EXPECT_TRUE(millnet::testing::linuxcnc_accepts((pr.out / (name + ".nc")).string()));
      }
    }
    if (std::string(v.tag) == "som-helix") {
      EXPECT_NE(pr.nc.find("helix entry"), std::string::npos);
    }
    if (v.predrill && num(pr.metrics, "predrill_points") > 0) {
      EXPECT_NE(pr.nc.find("PRE-DRILL"), std::string::npos);
    }
  }
  // The contour pass adds at least the length of the offset walls (> the boundary's inner offset's
  // shortest side); at the very least it adds cut length.
  EXPECT_GT(som_contour_cut, som_cut + 100);
}

INSTANTIATE_TEST_SUITE_P(Pockets, CliBenchPocket, ::testing::Values("comb", "four_islands", "eight_islands"));

TEST(CliPocket, StepDownsGiveEqualLevelsToTheFloor) {
  // depth 12, step-down 5 ⇒ ceil(12/5) = 3 equal levels at −4, −8, −12, each cutting the whole path.
  const auto d = fresh_dir("cli_pocket_levels");
  const PocketRun pr = run_pocket(bench("comb"), "--depth 12 --step-down 5", d);
  ASSERT_EQ(pr.r.code, 0) << pr.r.err;
  const ReplayResult rep = check_run(pr, "comb", replay_pocket_of(bench("comb")), 10, 12, true);
  ASSERT_EQ(rep.cut_length_by_z.size(), 3u);
  std::vector<double> zs, lens;
  for (const auto& [z, len] : rep.cut_length_by_z) {
    zs.push_back(z);
    lens.push_back(len);
  }
  EXPECT_EQ(zs, (std::vector<double>{-12, -8, -4}));
  EXPECT_NEAR(lens[0], lens[1], length_tol(lens[0]));
  EXPECT_NEAR(lens[1], lens[2], length_tol(lens[0]));
  EXPECT_NEAR(lens[0] + lens[1] + lens[2], rep.cut_length, length_tol(rep.cut_length));
  EXPECT_EQ(pr.metrics["parameters"]["depth"].get<double>(), 12);
  EXPECT_EQ(pr.metrics["parameters"]["step_down"].get<double>(), 5);
  // Between levels the tool goes up and comes down again: one tool-down chain per level, no more.
  EXPECT_EQ(num(pr.metrics, "retractions"), 2);
  EXPECT_EQ(num(pr.metrics, "plunges"), 3);
}

TEST(CliPocket, LinksRunAtTheChipThinnedFeedOfOneCellCappedByTheMachine) {
  // /pocket/air_feed (issue 11): the bench config cuts at 1500 mm/min with a 0.25 mm feed-map cell
  // on Ø10, so a move that cuts no cell runs at 1500 × D / (2·√(a_e(D − a_e))) with a_e = 0.25:
  // 1500 × 10 / (2·√2.4375) = 4803.8 mm/min (under the machine's 5000). The adaptive planner's
  // rides back along its fronts are such moves.
  const auto d = fresh_dir("cli_pocket_air_feed");
  const std::string bench_cfg = std::string(MILLNET_SOURCE_DIR) + "/configs/bench/roughing-issue11.json";
  const PocketRun pr = run_pocket(bench("comb"), "--config '" + bench_cfg + "' --planner adaptive", d / "a");
  ASSERT_EQ(pr.r.code, 0) << pr.r.err;
  EXPECT_NE(pr.nc.find("moves through cut material 4803.8;"), std::string::npos) << pr.nc.substr(0, 600);
  EXPECT_NE(pr.nc.find("F4803.8"), std::string::npos);
  // A slower machine caps it; the 1995 preset has none (every move at its cutting feed).
  json slow = json::parse(slurp(bench_cfg));
  slow["machine"]["max_feed_mm_min"] = 3000;
  std::ofstream(d / "slow.json") << slow.dump();
  const PocketRun capped =
      run_pocket(bench("comb"), "--config '" + (d / "slow.json").string() + "' --planner adaptive", d / "b");
  ASSERT_EQ(capped.r.code, 0) << capped.r.err;
  EXPECT_NE(capped.nc.find("moves through cut material 3000;"), std::string::npos) << capped.nc.substr(0, 600);
  EXPECT_EQ(capped.nc.find("F4803.8"), std::string::npos);
  const std::string preset = std::string(MILLNET_SOURCE_DIR) + "/configs/presets/shin-suh-1995.json";
  const PocketRun old = run_pocket(bench("comb"), "--config '" + preset + "' --planner zigzag --contour", d / "c");
  ASSERT_EQ(old.r.code, 0) << old.r.err;
  EXPECT_EQ(old.nc.find("moves through cut material"), std::string::npos);
}

TEST(CliPocket, SameCommandTwiceGivesSameBytes) {
  for (const char* flags : {"--planner som", "--planner zigzag --partition i --angle auto --contour"}) {
    const PocketRun a = run_pocket(bench("four_islands"), flags, fresh_dir("cli_pocket_det_a"));
    const PocketRun b = run_pocket(bench("four_islands"), flags, fresh_dir("cli_pocket_det_b"));
    ASSERT_EQ(a.r.code, 0) << a.r.err;
    ASSERT_EQ(b.r.code, 0) << b.r.err;
    EXPECT_FALSE(a.nc.empty());
    EXPECT_TRUE(a.nc == b.nc) << flags;
    EXPECT_EQ(slurp(a.out / "four_islands.points.csv"), slurp(b.out / "four_islands.points.csv")) << flags;
  }
}

TEST(CliPocket, FlagsOverrideConfigWhichOverridesThePocketFile) {
  const auto d = fresh_dir("cli_pocket_precedence");
  // A 60 × 40 rectangle whose file asks for Ø6, stepover 3, depth 4.
  std::ofstream(d / "p.json") << R"({"boundary": [[0,0,0],[60,0,0],[60,40,0],[0,40,0]], "islands": [],
    "tool_diameter": 6, "stepover": 3, "depth": 4})";
  std::ofstream(d / "c8.json") << R"({"pocket": {"tool_diameter": 8}})";
  std::ofstream(d / "c0.json") << R"({"pocket": {"planner": "som"}})";
  const ReplayPocket rect = replay_pocket_of(d / "p.json");
  auto params = [](const PocketRun& pr) { return pr.metrics["parameters"]; };
  {  // The file's own keys win over the defaults, and over a config that does not state them.
    for (const char* cfg : {"", "--config ../c0.json"}) {
      const PocketRun pr = run_pocket((d / "p.json").string(), std::string(cfg) + " --contour",
                                      d / (std::string("a") + (*cfg ? "c" : "")));
      ASSERT_EQ(pr.r.code, 0) << pr.r.err;
      EXPECT_EQ(params(pr)["tool_diameter"].get<double>(), 6) << cfg;
      EXPECT_EQ(params(pr)["stepover"].get<double>(), 3) << cfg;
      EXPECT_EQ(params(pr)["depth"].get<double>(), 4) << cfg;
      (void)check_run(pr, "p", rect, 6, 4, true);
    }
  }
  {  // The config states tool_diameter 8: it wins over the file's 6; the file's stepover stays.
    const PocketRun pr = run_pocket((d / "p.json").string(), "--config ../c8.json --contour", d / "b");
    ASSERT_EQ(pr.r.code, 0) << pr.r.err;
    EXPECT_EQ(params(pr)["tool_diameter"].get<double>(), 8);
    EXPECT_EQ(params(pr)["stepover"].get<double>(), 3);
    EXPECT_NE(pr.nc.find("(tool diameter 8"), std::string::npos) << pr.nc.substr(0, 400);
    (void)check_run(pr, "p", rect, 8, 4, true);
    // The path really is planned for Ø8: the contour pass runs at 4 mm from the walls, so a Ø9 disk
    // along it reaches 0.5 mm into them.
    ReplayResult rep = millnet::testing::replay_gcode(pr.nc, params(pr)["safe_z"].get<double>());
    millnet::testing::check_gouge(rep, rect, 4.5, kGougeTolMm, 0.05);
    EXPECT_NEAR(rep.worst_mm, 0.5, 0.02);
  }
  {  // Flags win over both.
    const PocketRun pr = run_pocket(
        (d / "p.json").string(), "--config ../c8.json --tool-diameter 7 --stepover 2.5 --depth 3 --contour", d / "c");
    ASSERT_EQ(pr.r.code, 0) << pr.r.err;
    EXPECT_EQ(params(pr)["tool_diameter"].get<double>(), 7);
    EXPECT_EQ(params(pr)["stepover"].get<double>(), 2.5);
    EXPECT_EQ(params(pr)["depth"].get<double>(), 3);
    EXPECT_NE(pr.nc.find("(tool diameter 7"), std::string::npos);
    (void)check_run(pr, "p", rect, 7, 3, true);
  }
}

TEST(CliPocket, BadPocketFilesExitOneWithOneLineNamingTheFile) {
  const auto d = fresh_dir("cli_pocket_bad");
  // Open DXF loop: three LINEs of a square.
  {
    std::ofstream f(d / "open.dxf");
    f << "0\nSECTION\n2\nENTITIES\n";
    const double seg[3][4] = {{0, 0, 40, 0}, {40, 0, 40, 40}, {40, 40, 0, 40}};
    for (const auto& s : seg)
      f << "0\nLINE\n8\n0\n10\n" << s[0] << "\n20\n" << s[1] << "\n11\n" << s[2] << "\n21\n" << s[3] << "\n";
    f << "0\nENDSEC\n0\nEOF\n";
  }
  std::ofstream(d / "bowtie.json") << R"({"boundary": [[0,0],[40,40],[40,0],[0,40]]})";
  std::ofstream(d / "island_out.json")
      << R"({"boundary": [[0,0],[50,0],[50,50],[0,50]], "islands": [[[100,10],[110,10],[110,20],[100,20]]]})";
  std::ofstream(d / "tiny.json") << R"({"boundary": [[0,0],[8,0],[8,8],[0,8]]})";
  const std::pair<const char*, const char*> cases[] = {
      {"open.dxf", "open loop"}, {"bowtie.json", "self-intersection"}, {"island_out.json", "outside"}};
  for (const auto& [file, what] : cases) {
    const auto r = run_millnet(std::string("pocket --pocket ") + file + " --quiet --out o_" + file, d);
    EXPECT_EQ(r.code, 1) << file << "\n" << r.err;
    EXPECT_EQ(lines_of(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_EQ(list_files(d / (std::string("o_") + file)), "") << file;
  }
  // A Ø10 tool fits nowhere in an 8 × 8 pocket: a clear status for both planners, no G-code file.
  for (const char* planner : {"som", "zigzag"}) {
    const fs::path out = d / (std::string("o_tiny_") + planner);
    const auto r = run_millnet(
        std::string("pocket --pocket tiny.json --planner ") + planner + " --quiet --out " + out.filename().string(), d);
    EXPECT_EQ(r.code, 1) << planner << "\n" << r.err;
    EXPECT_EQ(lines_of(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("tiny.json"), std::string::npos) << r.err;
    std::string lower = r.err;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return c == '_' ? ' ' : static_cast<char>(std::tolower(c)); });
    EXPECT_NE(lower.find("tool point"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "tiny.nc")) << list_files(out);
  }
}

TEST(CliPocket, DxfPocketWithBulgeAndCircleIsland) {
  const auto d = fresh_dir("cli_pocket_dxf");
  // LWPOLYLINE 0..80 × 0..50, closed, whose right edge (80,0)→(80,50) is an arc of bulge 0.5
  // (sweep 4·atan 0.5 ≈ 106°, sagitta 12.5 mm), and a CIRCLE island centre (35, 25) radius 8.
  std::ofstream(d / "arcs.dxf") << "0\nSECTION\n2\nENTITIES\n"
                                   "0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n"
                                   "10\n0\n20\n0\n10\n80\n20\n0\n42\n0.5\n10\n80\n20\n50\n10\n0\n20\n50\n"
                                   "0\nCIRCLE\n8\n0\n10\n35\n20\n25\n40\n8\n"
                                   "0\nENDSEC\n0\nEOF\n";
  ReplayPocket pocket;
  pocket.boundary = {{0, 0, 0}, {80, 0, 0.5}, {80, 50, 0}, {0, 50, 0}};
  pocket.islands = {{{27, 25, 1}, {43, 25, 1}}};  // two half circles
  for (const char* flags : {"--planner som --contour", "--planner zigzag --angle auto --contour"}) {
    SCOPED_TRACE(flags);
    const PocketRun pr = run_pocket((d / "arcs.dxf").string(), std::string(flags) + " --tool-diameter 6 --stepover 3",
                                    d / (std::string(flags).find("som") != std::string::npos ? "som" : "zz"));
    ASSERT_EQ(pr.r.code, 0) << pr.r.err;
    const ReplayResult rep = check_run(pr, "arcs", pocket, 6, 5, true);
    // The contour pass hugs the arc: some cutting sample lies beyond x = 80 (inside the bulge).
    double max_x = 0;
    for (const auto& m : rep.moves) {
      if (m.g == 0 || std::min(m.from[2], m.to[2]) >= 0) continue;
      max_x = std::max({max_x, m.from[0], m.to[0]});
      if (m.g == 2 || m.g == 3) {  // an arc through angle 0 reaches centre + radius
        const double rad = std::hypot(m.from[0] - m.center[0], m.from[1] - m.center[1]);
        const double a0 = std::atan2(m.from[1] - m.center[1], m.from[0] - m.center[0]);
        const double a1 = std::atan2(m.to[1] - m.center[1], m.to[0] - m.center[0]);
        const double ccw_from = m.g == 3 ? a0 : a1, ccw_to = m.g == 3 ? a1 : a0;
        double sweep = ccw_to - ccw_from;
        while (sweep <= 1e-12) sweep += 2 * kPi;
        double to_zero = -ccw_from;
        while (to_zero < 0) to_zero += 2 * kPi;
        if (to_zero <= sweep) max_x = std::max(max_x, m.center[0] + rad);
      }
    }
    EXPECT_GT(max_x, 80 + 12.5 - 3 - 1.0);
    EXPECT_LT(max_x, 80 + 12.5 - 3 + 1e-3);
  }
}

TEST(CliCompare, WritesOneRowPerPlannerConsistentWithPocket) {
  const auto d = fresh_dir("cli_compare");
  const auto r = run_millnet("compare --pocket '" + bench("four_islands") + "' --quiet --out D", d);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream csv(slurp(d / "D" / "compare.csv"));
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> head;
  {
    std::istringstream h(line);
    std::string c;
    while (std::getline(h, c, ',')) head.push_back(c);
  }
  auto col = [&](const char* k) {
    const auto it = std::find(head.begin(), head.end(), k);
    EXPECT_NE(it, head.end()) << k << " in " << line;
    return static_cast<std::size_t>(it - head.begin());
  };
  const std::size_t c_planner = col("planner"), c_cut = col("cut_length_mm"), c_ret = col("retractions"),
                    c_status = col("status");
  (void)col("rapid_length_mm");
  (void)col("planning_time_s");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::istringstream h(line);
    std::string c;
    while (std::getline(h, c, ',')) cells.push_back(c);
    ASSERT_EQ(cells.size(), head.size()) << line;
    rows.push_back(cells);
  }
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0][c_planner], "som");
  EXPECT_EQ(rows[1][c_planner], "zigzag-t");
  EXPECT_EQ(rows[2][c_planner], "zigzag-i");
  EXPECT_EQ(rows[3][c_planner], "offset");
  EXPECT_EQ(rows[4][c_planner], "adaptive");
  // Ranked by time to a cleared pocket: ranks 1..5, a cleared planner (uncut ≤ 2 mm²) before any
  // other, and among the cleared ones the shorter time on the machine first.
  const std::size_t c_rank = col("rank"), c_kin = col("time_kinematic_min"), c_uncut = col("uncut_area_mm2");
  (void)col("max_engagement_deg");
  std::vector<std::size_t> seen;
  for (const auto& row : rows) seen.push_back(std::stoul(row[c_rank]));
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<std::size_t>{1, 2, 3, 4, 5}));
  for (const auto& a : rows)
    for (const auto& b : rows) {
      const bool ca = std::stod(a[c_uncut]) <= 2, cb = std::stod(b[c_uncut]) <= 2;
      if (std::stoul(a[c_rank]) < std::stoul(b[c_rank])) {
        EXPECT_TRUE((ca && !cb) || (ca == cb && std::stod(a[c_kin]) <= std::stod(b[c_kin])))
            << a[c_planner] << " ranked before " << b[c_planner];
      }
    }
  EXPECT_EQ(rows[3][c_ret], "0");  // one reachable region: the offset planner never retracts
  for (const auto& row : rows) EXPECT_EQ(row[c_status], "ok") << row[c_planner];
  const std::string md = slurp(d / "D" / "compare.md");
  EXPECT_NE(md.find("Ranked by time to a cleared pocket"), std::string::npos);
  for (const char* p : {"| som |", "| zigzag-t |", "| zigzag-i |", "| offset |", "| adaptive |"})
    EXPECT_NE(md.find(p), std::string::npos) << p;
  for (const char* p : {"som", "zigzag-t", "zigzag-i"})
    EXPECT_TRUE(fs::exists(d / "D" / (std::string("four_islands.") + p + ".png"))) << list_files(d / "D");
  // Same pocket and tool through `millnet pocket`: the same figures.
  const PocketRun som = run_pocket(bench("four_islands"), "--planner som", d / "som");
  const PocketRun zt = run_pocket(bench("four_islands"), "--planner zigzag --partition t --angle auto", d / "zt");
  ASSERT_EQ(som.r.code, 0);
  ASSERT_EQ(zt.r.code, 0);
  EXPECT_NEAR(std::stod(rows[0][c_cut]), num(som.metrics, "cut_length_mm"), 1e-6);
  EXPECT_NEAR(std::stod(rows[0][c_ret]), num(som.metrics, "retractions"), 0);
  EXPECT_NEAR(std::stod(rows[1][c_cut]), num(zt.metrics, "cut_length_mm"), 1e-6);
  EXPECT_NEAR(std::stod(rows[1][c_ret]), num(zt.metrics, "retractions"), 0);
  // I-partition never needs more retractions than T-partition (Suh & Kim).
  EXPECT_LE(std::stod(rows[2][c_ret]), std::stod(rows[1][c_ret]));
}

// Issue 15: a 100,000-vertex boundary took 57 s (all-pairs validation) and then ~45 s in Clipper
// (every offset of the 3 µm-dense boundary). Planned and written within a few seconds of CPU now
// (the goal is 2 s; measured 1.2 s user + 0.3 s sys on the 2-core test machine). CPU time of the
// child, so that other work on the machine does not count.
TEST(CliPocket, HundredThousandVertexBoundaryIsPlannedQuickly) {
  const fs::path d = fresh_dir("pocket_100k");
  std::ostringstream b;
  b.precision(10);
  b << R"({"units": "mm", "boundary": [)";
  const int n = 100000;
  for (int k = 0; k < n; ++k)
    b << (k ? ", " : "") << "[" << 50 + 50 * std::cos(2 * std::numbers::pi * k / n) << ", "
      << 50 + 50 * std::sin(2 * std::numbers::pi * k / n) << "]";
  b << "]}";
  std::ofstream(d / "circle.json") << b.str();
  rusage before{}, after{};
  ::getrusage(RUSAGE_CHILDREN, &before);
  const CliResult r = run_millnet("pocket --pocket circle.json --out out --quiet", d, 120);
  ::getrusage(RUSAGE_CHILDREN, &after);
  auto secs = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  const double cpu = secs(after.ru_utime) - secs(before.ru_utime) + secs(after.ru_stime) - secs(before.ru_stime);
  std::printf("100,000-vertex pocket: %.2f s CPU\n", cpu);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "out" / "circle.nc"));
  RecordProperty("cpu_s", std::to_string(cpu));  // reported, not asserted: speed is measured, not tested
}

// Issue 42 §8: a plan that leaves more than pocket::kClearedUncutMm2 of the reachable area uncut
// said "status ok" and nothing else. Zigzag without its wall pass leaves the wedges along the walls:
// one warning line naming the pocket and the uncut area, and the metrics say "cleared": false with
// the same text; a cleared plan's metrics have neither key (they stay as they were).
TEST(CliPocket, APlanThatLeavesMaterialSaysSo) {
  const fs::path d = fresh_dir("cli_pocket/uncut_warning");
  const std::string sq = std::string(MILLNET_SOURCE_DIR) + "/tests/corpus/cli/square100.json";
  const CliResult r =
      run_millnet("pocket --pocket '" + sq + "' --planner zigzag --no-contour --quiet --out out", d, 120);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("warning: pocket: " + sq + ": the zigzag-i plan leaves "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" mm² uncut ("), std::string::npos) << r.err;
  const json m = json::parse(slurp(d / "out" / "square100.metrics.json"));
  EXPECT_EQ(m["status"], "ok");
  EXPECT_EQ(m["cleared"], false);
  EXPECT_GT(m["uncut_area_mm2"].get<double>(), 2.0);
  EXPECT_NE(m["warning"].get<std::string>().find("more than the 2 mm² a cleared pocket may leave"), std::string::npos);
  const CliResult ok = run_millnet("pocket --pocket '" + sq + "' --planner zigzag --quiet --out cleared", d, 120);
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err, "");
  const json c = json::parse(slurp(d / "cleared" / "square100.metrics.json"));
  EXPECT_LE(c["uncut_area_mm2"].get<double>(), 2.0);
  EXPECT_FALSE(c.contains("cleared"));
  EXPECT_FALSE(c.contains("warning"));
}
