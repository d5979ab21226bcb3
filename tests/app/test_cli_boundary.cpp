// Issue 38's boundaries from the command line: a 27 mm-deep cavity in a 42 mm-tall block finished
// with a ball that sticks out 35 mm. Checked against the depth the finishing machines (the cavity's
// floor, 28 mm below the stock top), not the part's base (43 mm); inside an outline file every cut
// stays in it and the surface is judged there; a Z range keeps every cut's tip within it.
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <variant>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

/// A 40 × 40 × 42 mm block with a 27 mm-deep cavity, |x − 20|, |y − 20| ≤ 8 at its floor (z = 15),
/// walls over 1 mm.
fs::path write_cavity_block(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r = std::max(std::abs(x - 20), std::abs(y - 20));
        return std::clamp(15 + 27 * (r - 8), 15.0, 42.0);
      },
      0, 40, 0, 40, 40, 40);
  const fs::path p = dir / "block.stl";
  ingest::save_stl_binary(m, p);
  return p;
}

/// The cutting moves' end points (program frame).
std::vector<gcode::Point3> cut_points(const fs::path& nc) {
  std::vector<gcode::Point3> out;
  for (const gcode::Item& i : gcode::read(slurp(nc), nc.string()).items)
    if (const auto* m = std::get_if<gcode::Move>(&i); m != nullptr && m->motion != gcode::Motion::Rapid)
      out.push_back(m->to);
  return out;
}

TEST(CliBoundary, ADeepCavityIsFinishedWithABallThatReachesItsFloorInsideAnOutline) {
  const fs::path d = fresh_dir("cli_boundary");
  const fs::path mesh = write_cavity_block(d);
  std::ofstream(d / "fast.json") << R"({"simulate": {"cell_mm": 0.1}})";
  std::ofstream(d / "box.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"boundary": {"on_part": false}}})";
  const std::string base = "finish -q --mesh '" + mesh.string() + "' --tool bn6-2f-carbide --strategy 2 --stepover 2 ";
  // The whole footprint with the table under it (the old box): the base, 43 mm below the stock top,
  // is beyond the ball's 35 mm.
  auto r = run_millnet(base + "--config box.json --out a", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("the part reaches 43.00 mm below the stock top, beyond the tool's stick-out 35 mm"),
            std::string::npos)
      << r.err;
  // Over the part (the default): the lowest cut is the cavity's floor, 28 mm down: accepted.
  r = run_millnet(base + "--config fast.json " + "--simulate --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  double lowest = 0;
  for (const gcode::Point3& q : cut_points(d / "b" / "block.s2.nc")) lowest = std::min(lowest, q[2]);
  EXPECT_NEAR(lowest, -28, 1e-3);
  // Inside the cavity's outline (a pocket file, program frame X Y): every cut inside it, the
  // surface judged there only (the cavity's floor and walls: ≤ 18 × 18 mm, not the block's 1,600).
  std::ofstream(d / "cavity.json") << R"({"boundary": [[11, 11], [29, 11], [29, 29], [11, 29]]})";
  r = run_millnet(base + "--config fast.json " + "--simulate --boundary cavity.json --out c", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto in_cavity = cut_points(d / "c" / "block.s2.nc");
  ASSERT_GT(in_cavity.size(), 20u);
  for (const gcode::Point3& q : in_cavity) {
    EXPECT_GE(q[0], 11 - 1e-3);
    EXPECT_LE(q[0], 29 + 1e-3);
    EXPECT_GE(q[1], 11 - 1e-3);
    EXPECT_LE(q[1], 29 + 1e-3);
  }
  const json all = json::parse(slurp(d / "b" / "block.s2.metrics.json"));
  const json inside = json::parse(slurp(d / "c" / "block.s2.metrics.json"));
  const double area_all = all["surface_cells"].get<double>() * 0.1 * 0.1;  // 0.1 mm cells
  const double area_in = inside["surface_cells"].get<double>() * 0.1 * 0.1;
  EXPECT_GT(area_all, 1500);
  EXPECT_LT(area_in, 18 * 18 + 1);
  EXPECT_GT(area_in, 16 * 16 - 1);
  // A Z range (program frame): only the floor's neighbourhood, every tip within it.
  r = run_millnet(base + "--config fast.json " + "--z-range -28.5 -20 --out e", d);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const gcode::Point3& q : cut_points(d / "e" / "block.s2.nc")) {
    EXPECT_GE(q[2], -28.5 - 1e-3);
    EXPECT_LE(q[2], -20 + 1e-3);
  }
  // Bad boundaries: one line naming the file or the flag.
  std::ofstream(d / "bad.json") << R"({"boundary": [[11, 11], [29, 11]]})";
  r = run_millnet(base + "--config fast.json " + "--boundary bad.json --out f", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
  r = run_millnet(base + "--config fast.json " + "--z-range -20 -28 --out g", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--z-range"), std::string::npos) << r.err;
}

// Issue 38: a STEP part's faces as the boundary, by name or index (tests/app/data/pocket_block.step:
// a 60 × 40 × 20 block, a 30 × 20 pocket 12 mm deep at X 15–45, Y 10–30, faces named in the file).
TEST(CliBoundary, TheFacesOfAStepPartKeepTheAxisOverThem) {
  const fs::path d = fresh_dir("cli_boundary_faces");
  const std::string step = std::string(MILLNET_SOURCE_DIR) + "/tests/app/data/pocket_block.step";
  std::ofstream(d / "faces.json") << R"({"finish": {"boundary": {"faces": ["pocket floor"]}}})";
  const std::string base =
      "finish -q --no-preview --mesh '" + step + "' --tool bn6-2f-carbide --strategy 2 --stepover 2 ";
  auto r = run_millnet(base + "--faces 'pocket floor' --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto floor = cut_points(d / "a" / "pocket_block.s2.nc");
  ASSERT_GT(floor.size(), 100U);
  for (const gcode::Point3& p : floor) {  // Z 0 = the stock top, 1 mm over the part's top at 20
    ASSERT_GE(p[0], 15 - 1e-6);
    ASSERT_LE(p[0], 45 + 1e-6);
    ASSERT_GE(p[1], 10 - 1e-6);
    ASSERT_LE(p[1], 30 + 1e-6);
  }
  const double lowest =
      std::min_element(floor.begin(), floor.end(), [](auto& a, auto& b) { return a[2] < b[2]; })->at(2);
  EXPECT_NEAR(lowest, 8 - 21, 1e-6);  // the floor, at the tip
  // The same faces from the config, and by index (the floor is the file's 11th face): the same program.
  r = run_millnet(base + "--config faces.json --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(d / "a" / "pocket_block.s2.nc"), slurp(d / "b" / "pocket_block.s2.nc"));
  r = run_millnet(base + "--faces 11 --out c", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(d / "a" / "pocket_block.s2.nc"), slurp(d / "c" / "pocket_block.s2.nc"));
  // Without a selection the top is finished too (over the part, the default).
  r = run_millnet(base + "--out e", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto all = cut_points(d / "e" / "pocket_block.s2.nc");
  EXPECT_TRUE(std::any_of(all.begin(), all.end(), [](const gcode::Point3& p) { return p[0] < 10; }));
  // Faces that do not exist, a name no face has, a mesh part: one line each, exit 1, nothing written.
  r = run_millnet(base + "--faces 12 --out f", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no face 12 (--faces / /finish/boundary/faces: the part has 11 faces, 1–11)"), std::string::npos)
      << r.err;
  r = run_millnet(base + "--faces floor --out f", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(
      r.err.find(
          R"(no face named "floor" (--faces / /finish/boundary/faces; named faces: "top", "pocket wall", "pocket floor"))"),
      std::string::npos)
      << r.err;
  // The walls alone are vertical: nothing of them is machined from above.
  r = run_millnet(base + "--faces 'pocket wall' --out f", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("selected triangles are all vertical"), std::string::npos) << r.err;
  const fs::path stl = write_cavity_block(d);
  r = run_millnet("finish -q --no-preview --mesh '" + stl.string() + "' --strategy 2 --faces 1 --out f", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("this part is a mesh without faces"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "f" / "pocket_block.s2.nc"));
  EXPECT_FALSE(fs::exists(d / "f" / "block.s2.nc"));
}

}  // namespace
}  // namespace millnet::testing
