// The model-vector table's estimate (issue 12 §1): rows × inputs per row, counted and refused in
// build_table before any part is read.
#include "millnet/core/error.hpp"
#include "millnet/datasets/build.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using namespace millnet::datasets;

TEST(DatasetsWork, TableValuesAreCountedBeforeAnyPartIsRead) {
  const fs::path d = fs::temp_directory_path() / "millnet_test_datasets_work";
  fs::remove_all(d);
  Recipe r;
  r.parts = to_part_specs(generate_default_parts(d / "parts", {3, 1, 40}));
  r.augment.angles_deg = {-20, 0, 30};
  r.grid = 7;
  r.raster_mm = 2.0;
  r.aspect_feature = true;
  // A sixth part that does not exist: never read, the table is refused first. 6 parts × 3 angles ×
  // {no flip, flip} = 36 rows × 7² inputs = 1,764 values.
  r.parts.push_back({d / "no_such_part.stl", 1, "missing", false});
  r.limits.max_work = 1499;
  try {
    (void)build_table(r);
    ADD_FAILURE() << "not refused";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("6 parts × their 36 augmented variants at grid 7 makes 1.8e3 model-vector "
                                         "table values (≈ 14 kB); the limit is 1.5e3 (--max-work, /limits/max_work)"),
              std::string::npos)
        << e.what();
  }
}
