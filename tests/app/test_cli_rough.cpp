// Issue 5, roughing through the CLI: the batch contract (a broken mesh is reported, the good one
// still gets its outputs) and the output files in the G-code frame, replayed against the mesh.
#include "cli_runner.hpp"
#include "config.hpp"
#include "testing/mesh_gouge.hpp"

#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace {

using millnet::app::Json;
using millnet::testing::GougeReport;
using millnet::testing::replay_against_mesh;
namespace ingest = millnet::ingest;
namespace datasets = millnet::datasets;
namespace fs = std::filesystem;
using millnet::testing::fresh_dir;
using millnet::testing::run_millnet;
using millnet::testing::slurp;

// ---------------------------------------------------------------------------------------------
// Outputs and the CLI.

TEST(RoughCli, BatchReportsTheBrokenMeshAndWritesTheGoodOnesOutputsInTheGcodeFrame) {
  const auto d = fresh_dir("rough_cli_batch");
  // The good part far from the origin, so that the frame contract (X/Y origin at the footprint's
  // lower-left after prepare, Z = 0 at the stock top) is exercised.
  const auto gen = datasets::make_part(datasets::Family::SteepPlateaus, 1, 7, 40);
  ingest::Mesh moved = gen.mesh;
  for (Eigen::Index i = 0; i < moved.V.rows(); ++i) moved.V.row(i) += Eigen::RowVector3d(250, -40, 13);
  ingest::save_stl_binary(moved, d / "good.stl");
  {
    std::ofstream f(d / "junk.stl", std::ios::binary);
    for (int i = 0; i < 1000; ++i) f.put(static_cast<char>((i * 7919) % 251));
  }
  const auto res =
      run_millnet("rough --mesh good.stl --mesh junk.stl --planner zigzag --stock-to-leave 0.5 --out o", d);
  EXPECT_EQ(res.code, 1) << res.err;
  EXPECT_NE(res.err.find("junk.stl"), std::string::npos) << res.err;
  EXPECT_EQ(res.err.find("good.stl"), std::string::npos) << res.err;
  const fs::path o = d / "o";
  ASSERT_TRUE(fs::exists(o / "good.nc")) << millnet::testing::list_files(o);
  EXPECT_FALSE(fs::exists(o / "junk.nc"));
  EXPECT_FALSE(fs::exists(o / "junk.metrics.json"));
  const Json summary = Json::parse(slurp(o / "rough_summary.json"));
  ASSERT_EQ(summary.size(), 2u);
  std::size_t errors = 0;
  for (const auto& s : summary)
    if (s["status"] == "error") {
      ++errors;
      EXPECT_EQ(s["part"], "junk");
      EXPECT_NE(s["error"].get<std::string>().find("junk.stl"), std::string::npos);
    } else {
      EXPECT_EQ(s["part"], "good");
    }
  EXPECT_EQ(errors, 1u);

  const Json m = Json::parse(slurp(o / "good.metrics.json"));
  EXPECT_EQ(m["status"], "ok");
  EXPECT_DOUBLE_EQ(m["stock_top_above_part_mm"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(m["stock_to_leave_mm"].get<double>(), 0.5);
  ASSERT_TRUE(m["per_level"].is_array());
  const std::size_t levels = m["levels"].get<std::size_t>();
  ASSERT_EQ(m["per_level"].size(), levels);
  const ingest::Mesh part = ingest::prepare(gen.mesh, {});
  const double part_top = part.V.col(2).maxCoeff();
  EXPECT_NEAR(m["stock"]["height_mm"].get<double>(), part_top + 1, 1e-4);  // STL is float32
  // The step-down levels, and a level per flat area not already kept (its flat + stock to leave + 0.002).
  std::size_t flat_levels = 0;
  for (const Json& lv : m["per_level"])
    if (!lv["flat_z_part_mm"].is_null()) {
      ++flat_levels;
      EXPECT_NEAR(lv["z_part_mm"].get<double>(), lv["flat_z_part_mm"].get<double>() + 0.5 + 0.002, 1e-9);
    }
  EXPECT_EQ(levels - flat_levels, static_cast<std::size_t>(std::ceil((part_top + 1) / 5 - 1e-9)));
  double prev = 0, cut_sum = 0;
  for (std::size_t k = 0; k < levels; ++k) {
    const Json& lv = m["per_level"][k];
    EXPECT_EQ(lv["level"].get<std::size_t>(), k + 1);
    EXPECT_LT(lv["z"].get<double>(), prev);
    EXPECT_LE(prev - lv["z"].get<double>(), 5 + 1e-9);
    prev = lv["z"].get<double>();
    for (const char* key : {"z_part_mm", "regions", "islands", "chains", "retractions", "cut_length_mm", "status"})
      EXPECT_TRUE(lv.contains(key)) << key;
    cut_sum += lv["cut_length_mm"].get<double>();
    const fs::path png = o / ("good.level_" + std::to_string(k + 1) + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  }
  EXPECT_NEAR(prev, -(part_top + 1), 1e-4);  // the last level at the part's lowest point
  EXPECT_FALSE(fs::exists(o / ("good.level_" + std::to_string(levels + 1) + ".png")));
  EXPECT_NEAR(cut_sum, m["cut_length_mm"].get<double>(), 1e-6 * cut_sum + 1e-6);

  // The program is in the promised frame: replayed against the part as prepared (moved back to
  // the origin), it never gouges, and it reaches the floor.
  const std::string gcode = slurp(o / "good.nc");
  const GougeReport g = replay_against_mesh(gcode, part, part_top + 1, 5, 0.5, 5);
  EXPECT_EQ(g.violations, 0) << g.first;
  EXPECT_GT(g.near, 100);
  EXPECT_NEAR(g.min_z, -(part_top + 1), 1e-3);
  // …and the same program 1.5 mm off in X gouges: the check sees the frame.
  ingest::Mesh off = part;
  for (Eigen::Index i = 0; i < off.V.rows(); ++i) off.V(i, 0) += 1.5;
  const GougeReport bad = replay_against_mesh(gcode, off, part_top + 1, 5, 0.5, 5);
  EXPECT_GT(bad.violations, 0) << "a 1.5 mm frame error went unnoticed";
}

}  // namespace
