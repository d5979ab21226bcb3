// The z-map's estimate (simulate::zmap_work, issue 12 §1): cells and bytes by hand, memory-only,
// and the refusal naming cell_mm and the memory limit.
#include "millnet/core/error.hpp"
#include "millnet/simulate/zmap.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace millnet;

TEST(SimulateWork, ZMapCellsAndBytes) {
  simulate::GridSpec g;
  g.cell = 0.02;
  g.nx = 5000;
  g.ny = 2400;
  const WorkEstimate e = simulate::zmap_work(g, 25);
  EXPECT_EQ(e.count, 5000.0 * 2400.0);
  EXPECT_EQ(e.bytes, 5000.0 * 2400.0 * (8 + 4 + 25));
  EXPECT_EQ(static_cast<double>(simulate::ZMap::bytes_needed(g)), 5000.0 * 2400.0 * 12);
  EXPECT_TRUE(e.memory_only);
  EXPECT_EQ(e.cause, "cell_mm 0.02 mm over a 100 × 48 mm z-map");
  // 1.2e7 cells × 37 B = 444 MB = 423.4 MiB: within 4 GiB, refused at 423 MiB, run at 424 MiB.
  EXPECT_NO_THROW(check_work(e, WorkLimits{}));
  EXPECT_NO_THROW(check_work(e, WorkLimits{1, 424.0 * 1024 * 1024}));
  try {
    check_work(e, WorkLimits{1e12, 423.0 * 1024 * 1024});
    ADD_FAILURE() << "not refused";
  } catch (const Error& x) {
    EXPECT_NE(std::string(x.what()).find("cell_mm 0.02 mm over a 100 × 48 mm z-map makes 1.2e7 z-map cells (≈ 444 MB); "
                                         "the memory limit is 423 MiB (--max-memory-mb, /limits/max_memory_mb)"),
              std::string::npos)
        << x.what();
  }
}
