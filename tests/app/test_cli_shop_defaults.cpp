// Issue 38's shop defaults, without a config: `finish` picks its ball from the library by the part
// (a 300 mm dome: the Ø10 ball at the specification's stepover, not the paper's Ø2 at p_f 0.2; a
// Ø100 mm block whose cavity has a 2.5 mm fillet: the Ø2, a 4 mm fillet: the Ø6 its size allows),
// and `rough` takes the offset planner and leaves 0.5 mm for the finishing (the preset
// configs/presets/rough-before-2026-11-27.json gives the roughing of before). Strategies whose pass
// spacing on the surface is bounded run at the feed radial chip thinning allows (hand-computed).
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

/// The program header's line that starts with `prefix` ("" when none).
std::string header_line(const fs::path& nc, const std::string& prefix) {
  std::istringstream in(slurp(nc));
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

/// A Ø100 mm round block 30 mm tall with a Ø45 mm cavity 15 mm deep whose wall meets its floor in a
/// fillet of radius `fillet`: the profile (radius, z) revolved in 180 steps, every ring a circle of
/// vertices (the centres of the floor and of the base one vertex each). Closed, outward normals.
ingest::Mesh filleted_cavity(double fillet) {
  std::vector<std::array<double, 2>> profile;  // from the floor's centre outwards and down to the base's
  profile.push_back({0, 15});
  const double c0 = 22.5 - fillet;
  for (int k = 0; k <= 16; ++k) {  // the fillet in 16 facets, from the floor (z 15) to the wall
    const double a = 0.5 * std::numbers::pi * k / 16;
    profile.push_back({c0 + fillet * std::sin(a), 15 + fillet - fillet * std::cos(a)});
  }
  profile.push_back({22.5, 30});
  profile.push_back({50, 30});
  profile.push_back({50, 0});
  profile.push_back({0, 0});
  constexpr int kSteps = 180;
  const int rings = static_cast<int>(profile.size()) - 2;  // every point but the two centres
  ingest::Mesh m;
  m.V.resize(2 + rings * kSteps, 3);
  m.V.row(0) << 50, 50, 15;
  m.V.row(1) << 50, 50, 0;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < kSteps; ++j) {
      const auto& p = profile[static_cast<std::size_t>(i + 1)];
      const double a = 2 * std::numbers::pi * j / kSteps;
      m.V.row(2 + i * kSteps + j) << 50 + p[0] * std::cos(a), 50 + p[0] * std::sin(a), p[1];
    }
  auto v = [&](int ring, int j) { return 2 + ring * kSteps + (j % kSteps); };
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j < kSteps; ++j) {
    f.push_back({0, v(0, j), v(0, j + 1)});                  // the floor's centre fan (normal up)
    f.push_back({1, v(rings - 1, j + 1), v(rings - 1, j)});  // the base's (normal down)
    for (int i = 0; i + 1 < rings; ++i) {                    // outwards along the profile
      f.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      f.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  }
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t k = 0; k < f.size(); ++k) m.F.row(static_cast<Eigen::Index>(k)) << f[k][0], f[k][1], f[k][2];
  return m;
}

/// A W × D mm block `base` mm tall under a dome `height` mm high at its centre, on an nx × ny grid.
void write_dome(const fs::path& file, double w, double d, double base, double height, int nx, int ny) {
  ingest::save_stl_binary(testing_ingest::solid(
                              [=](double x, double y) {
                                const double u = (x - w / 2) / (w / 2), v = (y - d / 2) / (d / 2);
                                return base + height * std::max(0.0, 1 - 0.5 * (u * u + v * v));
                              },
                              0, w, 0, d, nx, ny),
                          file);
}

TEST(CliShopDefaults, FinishPicksItsBallByThePartsSizeAndConcaveRadius) {
  const fs::path d = fresh_dir("cli_shop_finish");
  // A 300 × 200 mm dome, 20 mm high (convex: no concave radius bounds the ball).
  write_dome(d / "dome.stl", 300, 200, 10, 20, 60, 40);
  auto r = run_millnet("finish -q --mesh dome.stl --strategy 2 --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string tool = header_line(d / "a" / "dome.s2.nc", "(tool: ");
  EXPECT_NE(tool.find("bn10-2f-carbide"), std::string::npos) << tool;
  const json m = json::parse(slurp(d / "a" / "dome.s2.metrics.json"));
  // The default specification's 0.005 mm cusp with a 5 mm radius: 2·√(2·5·0.005) = 0.447 mm.
  EXPECT_NEAR(m["params"]["stepover_mm"].get<double>(), 2 * std::sqrt(2 * 5 * 0.005 - 0.005 * 0.005), 1e-3)
      << m["params"].dump();
  // Naming the tool keeps it (the paper's Ø2).
  r = run_millnet("finish -q --mesh dome.stl --strategy 2 --tool bn2-2f-carbide --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(header_line(d / "b" / "dome.s2.nc", "(tool: ").find("bn2-2f-carbide"), std::string::npos);

  // A round block Ø100 mm (its size alone allows Ø6.7: the Ø6 ball) with a cavity whose wall meets
  // its floor in a fillet, tessellated as CAD tessellates a fillet (along its generators): a 2.5 mm
  // fillet admits Ø5, so the Ø2 finishes it; a 4 mm fillet admits Ø8, so the size decides (Ø6).
  for (const double fillet : {2.5, 4.0}) {
    const std::string name = fillet < 3 ? "tight" : "wide";
    ingest::save_stl_binary(filleted_cavity(fillet), d / (name + ".stl"));
    r = run_millnet("finish --mesh " + name + ".stl --strategy 4 --out " + name, d);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string ball = fillet < 3 ? "bn2-2f-carbide" : "bn6-2f-carbide";
    EXPECT_NE(header_line(d / name / (name + ".s4.nc"), "(tool: ").find(ball), std::string::npos) << name;
    EXPECT_NE(r.err.find("finishing tool " + ball + ": the part's 100.0 mm footprint allows Ø6.7"), std::string::npos)
        << r.err;
    const auto at = r.err.find("smallest concave radius ");
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_NEAR(std::stod(r.err.substr(at + 24, 6)), fillet, 0.02 * fillet) << r.err;
  }
}

TEST(CliShopDefaults, RoughTakesTheOffsetPlannerAndLeavesStockForTheFinishing) {
  const fs::path d = fresh_dir("cli_shop_rough");
  ingest::save_stl_binary(
      testing_ingest::solid([](double x, double y) { return 10 + 5 * std::sin(x / 10) * std::cos(y / 12); }, 0, 50, 0,
                            40, 50, 40),
      d / "part.stl");
  auto r = run_millnet("rough -q --mesh part.stl --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  json m = json::parse(slurp(d / "a" / "part.metrics.json"));
  EXPECT_EQ(m["planner"], "offset");
  EXPECT_EQ(m["stock_to_leave_mm"].get<double>(), 0.5);
  // The roughing of before, by its preset.
  const std::string preset = std::string(MILLNET_SOURCE_DIR) + "/configs/presets/rough-before-2026-11-27.json";
  r = run_millnet("rough -q --config '" + preset + "' --mesh part.stl --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  m = json::parse(slurp(d / "b" / "part.metrics.json"));
  EXPECT_EQ(m["planner"], "som");
  EXPECT_EQ(m["stock_to_leave_mm"].get<double>(), 0);
  // A flag still wins over the default.
  r = run_millnet("rough -q --mesh part.stl --planner zigzag --stock-to-leave 0.2 --out c", d);
  ASSERT_EQ(r.code, 0) << r.err;
  m = json::parse(slurp(d / "c" / "part.metrics.json"));
  EXPECT_EQ(m["planner"], "zigzag");
  EXPECT_EQ(m["stock_to_leave_mm"].get<double>(), 0.2);
}

TEST(CliShopDefaults, TheStockBlockIsGivenBySideOrBySizeAndTheWorkOriginSitsOnIt) {
  const fs::path d = fresh_dir("cli_shop_stock");
  ingest::save_stl_binary(
      testing_ingest::solid([](double x, double y) { return 10 + 5 * std::sin(x / 10) * std::cos(y / 12); }, 0, 50, 0,
                            40, 50, 40),
      d / "part.stl");  // footprint 50 × 40 mm
  auto stock_of = [&](const std::string& dir) {
    const json m = json::parse(slurp(d / dir / "part.metrics.json"));
    const json& s = m["stock"];
    return std::array<double, 4>{s["x0"].get<double>(), s["x1"].get<double>(), s["y0"].get<double>(),
                                 s["y1"].get<double>()};
  };
  // A saw-cut blank: 2 mm left of the part, 20 right, 5 front and back; the origin at its corner.
  std::ofstream(d / "sides.json")
      << R"({"rough": {"stock_offsets_mm": [2, 20, 5, 5]}, "machine": {"work_origin": "stock_corner"}})";
  auto r = run_millnet("rough -q --config sides.json --mesh part.stl --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  auto s = stock_of("a");
  EXPECT_NEAR(s[0], -2, 1e-9);
  EXPECT_NEAR(s[1], 70, 1e-9);
  EXPECT_NEAR(s[2], -5, 1e-9);
  EXPECT_NEAR(s[3], 45, 1e-9);
  EXPECT_NE(header_line(d / "a" / "part.nc",
                        "(work origin: X0 Y0 = the stock's lower-left corner [the part's "
                        "lower-left corner at X2 Y5 mm])"),
            "");
  // Its centre: ((−2 + 70) / 2, (−5 + 45) / 2) = (34, 20) in the part's frame.
  std::ofstream(d / "centre.json")
      << R"({"rough": {"stock_offsets_mm": [2, 20, 5, 5]}, "machine": {"work_origin": "stock_centre"}})";
  r = run_millnet("rough -q --config centre.json --mesh part.stl --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(header_line(d / "b" / "part.nc",
                        "(work origin: X0 Y0 = the stock's centre [the part's lower-left "
                        "corner at X-34 Y-20 mm])"),
            "");
  // A pre-cut 80 × 60 mm blank, centred: 15 mm and 10 mm each side.
  std::ofstream(d / "size.json") << R"({"rough": {"stock_size_mm": [80, 60]}})";
  r = run_millnet("rough -q --config size.json --mesh part.stl --out c", d);
  ASSERT_EQ(r.code, 0) << r.err;
  s = stock_of("c");
  EXPECT_NEAR(s[0], -15, 1e-9);
  EXPECT_NEAR(s[1], 65, 1e-9);
  EXPECT_NEAR(s[2], -10, 1e-9);
  EXPECT_NEAR(s[3], 50, 1e-9);
  // Refused in one line: a blank smaller than the part, both keys, a side too many.
  auto refused = [&](const std::string& config, const std::string& what) {
    std::ofstream(d / "bad.json") << config;
    const auto bad = run_millnet("rough --config bad.json --mesh part.stl --out bad", d);
    EXPECT_EQ(bad.code, 1) << bad.err;
    EXPECT_NE(bad.err.find(what), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_FALSE(fs::exists(d / "bad" / "part.nc"));
  };
  refused(R"({"rough": {"stock_size_mm": [45, 60]}})",
          "/rough/stock_size_mm: a block of 45 × 60 mm is smaller than the part's footprint 50 × 40 mm");
  refused(R"({"rough": {"stock_size_mm": [80, 60], "stock_offsets_mm": [1, 1, 1, 1]}})", "write one of them");
  refused(R"({"rough": {"stock_offsets_mm": [1, 1, 1, 1, 1]}})", "/rough/stock_offsets_mm: expected at most 4 items");
}

TEST(CliShopDefaults, BoundedEngagementFinishingRunsAtTheChipThinnedFeed) {
  const fs::path d = fresh_dir("cli_shop_thinning");
  write_dome(d / "dome.stl", 40, 30, 5, 8, 40, 30);
  // Ø6 ball in 6061: fz 0.05 × 2 × 24,000 rpm (the machine's limit) = 2400 mm/min. D_eff at the
  // 0.1 mm allowance 2·√(0.1·5.9) = 1.5362 mm; the spec's spacing 2·√(2·3·0.005 − 0.005²) = 0.34634 mm;
  // k = 1.5362 / (2·√(0.34634·(1.5362 − 0.34634))) = 1.1965: 2872 mm/min.
  const double deff = 2 * std::sqrt(0.1 * 5.9), w = 2 * std::sqrt(2 * 3 * 0.005 - 0.005 * 0.005);
  const double thinned = std::round(2400 * deff / (2 * std::sqrt(w * (deff - w))));
  ASSERT_EQ(thinned, 2872);
  auto feeds = [&](const fs::path& nc) {  // the F words of the program
    std::set<int> f;
    std::istringstream in(slurp(nc));
    for (std::string line; std::getline(in, line);)
      if (const auto at = line.find(" F"); line.rfind("G1", 0) == 0 && at != std::string::npos)
        f.insert(std::stoi(line.substr(at + 2)));
    return f;
  };
  auto r = run_millnet("finish -q --mesh dome.stl --tool bn6-2f-carbide --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const int slot : {1, 3, 5}) {  // bounded spacing on the surface: thinned
    const fs::path nc = d / "a" / ("dome.s" + std::to_string(slot) + ".nc");
    EXPECT_TRUE(feeds(nc).count(2872)) << slot;
    EXPECT_FALSE(feeds(nc).count(2400)) << slot;
    EXPECT_NE(header_line(nc, "(feed 2400 -> 2872 mm/min: radial chip thinning"), "") << slot;
  }
  for (const int slot : {2, 4}) {  // raster and Z-level: the spacing grows on steep or flat areas
    const fs::path nc = d / "a" / ("dome.s" + std::to_string(slot) + ".nc");
    EXPECT_TRUE(feeds(nc).count(2400)) << slot;
    EXPECT_FALSE(feeds(nc).count(2872)) << slot;
  }
  // Chip thinning off (/cutting/max_chip_thinning 1) or the feed written: every strategy at it.
  std::ofstream(d / "off.json") << R"({"cutting": {"max_chip_thinning": 1}})";
  std::ofstream(d / "feed.json") << R"({"finish": {"feed_mm_min": 2000}})";
  for (const std::string c : {"off", "feed"}) {
    r = run_millnet("finish -q --config " + c + ".json --mesh dome.stl --tool bn6-2f-carbide --strategy 5 --out " + c,
                    d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(feeds(d / c / "dome.s5.nc"), (std::set<int>{c == "off" ? 2400 : 2000, 720})) << c;
  }
}

}  // namespace
}  // namespace millnet::testing
