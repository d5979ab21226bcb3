// datasets::model_vectors: the prediction path gives the very rows the dataset build stores.
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/features.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

namespace {

namespace datasets = millnet::datasets;
namespace ingest = millnet::ingest;
namespace fs = std::filesystem;

/// A fresh folder test_tmp/<name> holding part.stl, a generated deep cavity (seed 7).
fs::path deep_cavity_part(const std::string& name) {
  const fs::path dir = fs::path(MILLNET_BINARY_DIR) / "test_tmp" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  ingest::save_stl_binary(datasets::make_part(datasets::Family::DeepCavity, 0, 7, 40).mesh, dir / "part.stl");
  return dir;
}

TEST(ModelVectors, EqualTheBuiltTableRowsBitForBit) {
  const fs::path dir = deep_cavity_part("features");
  datasets::Recipe recipe;
  recipe.parts = {{dir / "part.stl", 4, "part"}};
  recipe.raster_mm = 1.0;
  recipe.grid = 15;
  const datasets::Table table = datasets::build_table(recipe);

  datasets::FeatureSpec spec;
  spec.raster_mm = recipe.raster_mm;
  spec.grid = recipe.grid;
  spec.augment = recipe.augment;
  const ingest::Mesh mesh = ingest::prepare(ingest::load_mesh(dir / "part.stl"), {});
  const datasets::ModelVectors mv = datasets::model_vectors(mesh, "part", spec);
  ASSERT_EQ(static_cast<std::size_t>(mv.inputs.rows()), table.rows.size());
  ASSERT_EQ(mv.variants.size(), table.rows.size());
  for (std::size_t v = 0; v < table.rows.size(); ++v) {
    EXPECT_EQ(mv.variants[v].angle_deg, table.rows[v].angle_deg);
    for (std::size_t c = 0; c < table.rows[v].inputs.size(); ++c)
      ASSERT_EQ(mv.inputs(static_cast<Eigen::Index>(v), static_cast<Eigen::Index>(c)), table.rows[v].inputs[c])
          << "variant " << v << " column " << c;
  }
}

}  // namespace

namespace {

/// One triangle of area 1/2 in the plane through the origin with `normal` (an upward or downward
/// facet), as a mesh of its own.
ingest::Mesh facet(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u =
      (std::abs(n.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX()).cross(n).normalized();
  const Eigen::Vector3d v = n.cross(u);
  ingest::Mesh m;
  m.V.resize(3, 3);
  m.V.row(0) = Eigen::Vector3d::Zero().transpose();
  m.V.row(1) = u.transpose();
  m.V.row(2) = v.transpose();
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  return m;
}

ingest::Mesh joined(const std::vector<ingest::Mesh>& parts) {
  ingest::Mesh m;
  Eigen::Index nv = 0, nf = 0;
  for (const auto& p : parts) nv += p.V.rows(), nf += p.F.rows();
  m.V.resize(nv, 3);
  m.F.resize(nf, 3);
  nv = nf = 0;
  for (const auto& p : parts) {
    m.V.middleRows(nv, p.V.rows()) = p.V;
    m.F.middleRows(nf, p.F.rows()) = p.F.array() + static_cast<int>(nv);
    nv += p.V.rows(), nf += p.F.rows();
  }
  return m;
}

Eigen::Vector3d tilted(double deg) {
  const double r = deg * std::numbers::pi / 180;
  return {std::sin(r), 0, std::cos(r)};
}

}  // namespace

// Issue 39 §3: the wall share by hand — four facets of equal area: flat, 45°, 70° and 89° (two
// walls of four upward facets: 0.5), a vertical side and a downward facet left out; 59.9° is no
// wall, 60.1° is; no upward facet gives 0.
TEST(WallShare, IsTheAreaShareOfUpwardFacetsSteeperThan60Degrees) {
  EXPECT_DOUBLE_EQ(datasets::wall_share(joined({facet(tilted(0)), facet(tilted(45)), facet(tilted(70)),
                                                facet(tilted(89)), facet({1, 0, 0}), facet({0, 0.3, -1})})),
                   0.5);
  EXPECT_DOUBLE_EQ(datasets::wall_share(joined({facet(tilted(59.9)), facet(tilted(60.1))})), 0.5);
  EXPECT_DOUBLE_EQ(datasets::wall_share(facet(tilted(59.9))), 0.0);
  EXPECT_DOUBLE_EQ(datasets::wall_share(facet({0, 0, -1})), 0.0);
}

// The prediction path appends the wall share as the model asks (FeatureSpec::wall_share_copies)
// and the table build stores the same value on every variant of the part.
TEST(ModelVectors, CarryThePartsWallShareAfterTheHeights) {
  const fs::path dir = deep_cavity_part("features_wall");
  datasets::Recipe recipe;
  recipe.parts = {{dir / "part.stl", 4, "part"}};
  recipe.wall_share_feature = true;
  const datasets::Table table = datasets::build_table(recipe);
  ASSERT_TRUE(table.has_wall_share);
  const ingest::Mesh mesh = ingest::prepare(ingest::load_mesh(dir / "part.stl"), {});
  const double w = datasets::wall_share(mesh);
  EXPECT_GT(w, 0.25) << "a deep cavity's walls are ≥ 25 % of its surface (datasets/README.md)";
  for (const auto& r : table.rows) EXPECT_EQ(r.wall_share, w) << r.id;
  datasets::FeatureSpec spec;
  spec.augment = recipe.augment;
  spec.wall_share_copies = 3;
  const datasets::ModelVectors mv = datasets::model_vectors(mesh, "part", spec);
  ASSERT_EQ(mv.inputs.cols(), 225 + 3);
  for (Eigen::Index v = 0; v < mv.inputs.rows(); ++v) {
    for (Eigen::Index c = 225; c < 228; ++c) EXPECT_EQ(mv.inputs(v, c), w);
    for (Eigen::Index c = 0; c < 225; ++c)
      ASSERT_EQ(mv.inputs(v, c), table.rows[static_cast<std::size_t>(v)].inputs[static_cast<std::size_t>(c)]);
  }
}
