// datasets::model_vectors: the prediction path gives the very rows the dataset build stores.
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/features.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace {

namespace datasets = millnet::datasets;
namespace ingest = millnet::ingest;
namespace fs = std::filesystem;

TEST(ModelVectors, EqualTheBuiltTableRowsBitForBit) {
  const fs::path dir = fs::path(MILLNET_BINARY_DIR) / "test_tmp" / "features";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto gen = datasets::make_part(datasets::Family::DeepCavity, 0, 7, 40);
  ingest::save_stl_binary(gen.mesh, dir / "part.stl");
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
