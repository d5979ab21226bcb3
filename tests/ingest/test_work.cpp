// Height-field raster estimates (ingest::raster_work, issue 12 §1) against hand-computed counts, and
// rasterize_top's guard: refused over the limit, run at exactly the estimate.
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"

#include "builders.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace millnet;

TEST(IngestWork, RasterPointsOfA100mmFootprintAtOneMm) {
  const WorkEstimate e = ingest::raster_work(100, 100, 1);
  EXPECT_EQ(e.count, 101.0 * 101.0);  // ⌈100 / 1⌉ + 1 per side, as rasterize_top sizes it
  EXPECT_EQ(e.bytes, 9.0 * 101 * 101);
  EXPECT_EQ(e.cause, "raster_mm 1 mm over a 100 × 100 mm footprint");
  EXPECT_EQ(ingest::raster_work(60, 40, 0.0001, "stock").count, 600001.0 * 400001.0);
}

TEST(IngestWork, EstimateMatchesTheRasterAndTheGuardIsExact) {
  const ingest::Mesh m = testing_ingest::box(0, 0, 0, 30, 20, 5);
  const WorkEstimate e = ingest::raster_work(m, 0.5);
  const ingest::HeightField f = ingest::rasterize_top(m, 0.5, WorkLimits{e.count, 1e9});
  EXPECT_EQ(static_cast<double>(f.z.size()), e.count);
  try {
    (void)ingest::rasterize_top(m, 0.5, WorkLimits{e.count - 1, 1e9});
    ADD_FAILURE() << "not refused";
  } catch (const Error& x) {
    EXPECT_NE(std::string(x.what()).find("raster_mm 0.5 mm over a 30 × 20 mm mesh footprint makes 2.501e3 "
                                         "height-field raster points"),
              std::string::npos)
        << x.what();
  }
}
