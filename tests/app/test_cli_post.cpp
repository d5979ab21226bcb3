// The controller's dialect (issue 36 §2): pocket, rough and finish write every program in the
// dialect of /machine/post or --post. The GRBL programs pass an independent check of GRBL 1.1's
// grammar (tests/testing/grbl_check.hpp); a GRBL program machines the same z-map as the LinuxCNC one.
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"
#include "testing/grbl_check.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <fstream>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;

/// A dome (max 6 mm) on a 16 × 12 mm block 1 mm thick, as ASCII STL.
fs::path write_dome(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r2 = (x - 8) * (x - 8) / 36 + (y - 6) * (y - 6) / 16;
        return 1 + 5 * std::max(0.0, 1 - r2);
      },
      0, 16, 0, 12, 32, 24);
  const fs::path p = dir / "dome.stl";
  std::ofstream out(p);
  out << "solid dome\n";
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto v = m.V.row(m.F(f, k));
      out << "   vertex " << v(0) << " " << v(1) << " " << v(2) << "\n";
    }
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid dome\n";
  return p;
}

void expect_grbl_accepts(const fs::path& nc) {
  const std::string text = slurp(nc);
  ASSERT_FALSE(text.empty()) << nc;
  const auto errors = grbl_errors(text);
  EXPECT_TRUE(errors.empty()) << nc << "\n" << grbl_report(errors);
  EXPECT_EQ(text.find("M6"), std::string::npos) << nc;
}

TEST(CliPost, FinishRoughAndPocketWriteGrblThatGrblAccepts) {
  const fs::path d = fresh_dir("post_grbl");
  const fs::path mesh = write_dome(d);
  std::ofstream(d / "fast.json") << R"({"simulate": {"cell_mm": 0.05}})";
  const auto f = run_millnet("finish --quiet --no-preview --config fast.json --mesh '" + mesh.string() +
                                 "' --strategy all --stepover 0.5 --step-down 0.5 --post grbl --out fin",
                             d);
  ASSERT_EQ(f.code, 0) << f.err;
  for (int k = 1; k <= 5; ++k) expect_grbl_accepts(d / "fin" / ("dome.s" + std::to_string(k) + ".nc"));
  // The dialect from the config instead of the flag.
  std::ofstream(d / "grbl.json") << R"({"machine": {"post": "grbl"}})";
  const auto r = run_millnet(
      "rough --quiet --no-preview --config grbl.json --mesh '" + mesh.string() + "' --step-down 2 --out rough", d);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_grbl_accepts(d / "rough" / "dome.nc");
  // A 60 × 40 mm pocket with a round island (bulge 1: two half circles), 5 mm deep, a Ø10 tool.
  std::ofstream(d / "small.json") << R"({"units": "mm", "boundary": [[0, 0, 0], [60, 0, 0], [60, 40, 0], [0, 40, 0]],
    "islands": [[[35, 20, 1], [25, 20, 1]]], "tool_diameter": 10, "stepover": 5, "depth": 5})";
  const std::string pocket = (d / "small.json").string();
  for (const char* planner : {"som", "offset", "adaptive", "zigzag"}) {
    SCOPED_TRACE(planner);
    const std::string out = std::string("pocket_") + planner;
    // som and zigzag enter by pre-drilling: the drill and the pause for the end mill are in the program
    const auto p =
        run_millnet("pocket --quiet --no-preview --pocket '" + pocket + "' --planner " + planner +
                        (std::string(planner) == "adaptive" ? " --entry helix" : "") + " --post grbl --out " + out,
                    d);
    ASSERT_EQ(p.code, 0) << p.err;
    expect_grbl_accepts(d / out / "small.nc");
  }
  const auto bad = run_millnet("pocket --pocket '" + pocket + "' --post fanuc16 --out x", d);
  EXPECT_EQ(bad.code, 1) << bad.err;
  EXPECT_NE(bad.err.find("--post: fanuc16 not in {linuxcnc,grbl,fanuc}"), std::string::npos) << bad.err;
}

TEST(CliPost, AGrblProgramMachinesTheSameSurfaceAsTheLinuxcncOne) {
  const fs::path d = fresh_dir("post_same_zmap");
  const fs::path mesh = write_dome(d);
  std::ofstream(d / "fast.json") << R"({"simulate": {"cell_mm": 0.05}})";
  for (const char* post : {"linuxcnc", "grbl", "fanuc"}) {
    const auto f =
        run_millnet("finish --quiet --no-preview --config fast.json --mesh '" + mesh.string() +
                        "' --tool bn2-2f-carbide --strategy 3 --stepover 0.5 --post " + post + " --out " + post,
                    d);
    ASSERT_EQ(f.code, 0) << f.err;
    const auto s = run_millnet("simulate --quiet --no-preview --config fast.json --mesh '" + mesh.string() +
                                   "' --gcode " + post + "/dome.s3.nc --tool ball:2 --stock design --out sim_" + post,
                               d);
    ASSERT_EQ(s.code, 0) << s.err;
  }
  EXPECT_NE(slurp(d / "linuxcnc" / "dome.s3.nc"), slurp(d / "grbl" / "dome.s3.nc"));
  auto a = nlohmann::json::parse(slurp(d / "sim_linuxcnc" / "dome.sim.json"));
  auto b = nlohmann::json::parse(slurp(d / "sim_grbl" / "dome.sim.json"));
  a.erase("programs"), b.erase("programs");  // they name their files
  EXPECT_EQ(a.dump(), b.dump());
  EXPECT_EQ(slurp(d / "sim_linuxcnc" / "dome.deviation.png"), slurp(d / "sim_grbl" / "dome.deviation.png"));
  // The Fanuc text rounds to its 0.001 mm increment: the same surface within that, no gouge.
  auto c = nlohmann::json::parse(slurp(d / "sim_fanuc" / "dome.sim.json"));
  const std::string fanuc = slurp(d / "fanuc" / "dome.s3.nc");
  EXPECT_EQ(fanuc.rfind("%\nO1000\n", 0), 0u) << fanuc.substr(0, 200);
  for (const char* key : {"ra_median_um", "scallop_max_mm", "max_gouge_mm"}) {
    const auto find = [&](const nlohmann::json& j) {
      for (const auto& [k, v] : j.items())
        if (k == key) return v.get<double>();
      for (const auto& [k, v] : j.items())
        if (v.is_object() && v.contains(key)) return v[key].get<double>();
      return -1.0;
    };
    const double x = find(a), y = find(c);
    ASSERT_GE(x, 0) << key;
    EXPECT_NEAR(x, y, std::string(key) == "ra_median_um" ? 0.05 : 0.002) << key;
  }
}

}  // namespace
}  // namespace millnet::testing
