// Zigzag regions joined with the tool down (ZigzagParams::link_regions, issue 11): against the same
// plan without links, every link saves one retraction and one entry (the wall pass's loops are
// joined too), the G-code never gouges (independent replay), and an independent raster oracle finds
// the linked plan cutting what the regions cut on their own, plus only the wall band the contour
// pass sweeps anyway.
#include "testing/program_text.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

using namespace millnet::pocket;
using millnet::testing::to_replay;

namespace {

CutParams bench_cut() { return millnet::testing::issue11_bench_cut(); }

/// Cells of h mm swept by a disk of radius r along the chains' segments (in order), with a probe
/// that counts, before a segment is stamped, its swept cells that are still uncut.
struct Raster {
  Vec2 lo;
  double h;
  long nx, ny;
  std::vector<char> cut;
  Raster(Vec2 lo_, Vec2 hi, double h_) : lo(lo_), h(h_) {
    nx = std::lround((hi.x() - lo.x()) / h) + 1;
    ny = std::lround((hi.y() - lo.y()) / h) + 1;
    cut.assign(static_cast<std::size_t>(nx * ny), 0);
  }
  template <class F>
  void disk_cells(const Vec2& c, double r, F&& f) const {
    const long cx = std::lround((c.x() - lo.x()) / h), cy = std::lround((c.y() - lo.y()) / h);
    const long rc = static_cast<long>(std::ceil(r / h)) + 1;
    for (long dy = -rc; dy <= rc; ++dy)
      for (long dx = -rc; dx <= rc; ++dx) {
        const long gx = cx + dx, gy = cy + dy;
        if (gx < 0 || gy < 0 || gx >= nx || gy >= ny) continue;
        if (std::hypot(lo.x() + static_cast<double>(gx) * h - c.x(), lo.y() + static_cast<double>(gy) * h - c.y()) <= r)
          f(gy * nx + gx);
      }
  }
  template <class F>
  void segment_cells(const Vec2& a, const Vec2& b, double r, F&& f) const {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * h))));
    for (int k = 0; k <= n; ++k) disk_cells(a + (b - a) * (static_cast<double>(k) / n), r, f);
  }
  void stamp(const Vec2& a, const Vec2& b, double r) {
    segment_cells(a, b, r, [&](long c) { cut[static_cast<std::size_t>(c)] = 1; });
  }
};

struct LinkCase {
  const char* pocket;
  PartitionKind partition;
};
// Stable test names for ctest (gtest_discover_tests keeps the printed parameter in the name; the
// default printer shows the string's address).
void PrintTo(const LinkCase& c, std::ostream* os) {
  *os << c.pocket << (c.partition == PartitionKind::T ? " T" : " I");
}

class ZigzagLinks : public ::testing::TestWithParam<LinkCase> {};

TEST_P(ZigzagLinks, RegionsJoinedThroughCutMaterialSaveARetractionAndAnEntryEach) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + GetParam().pocket + ".json");
  const CutParams cut = bench_cut();
  ZigzagParams zp;
  zp.angle_deg = std::nullopt;
  zp.partition = GetParam().partition;
  zp.link_regions = false;
  const PlanResult alone = plan(pf.region, cut, ZigzagSpec{zp});
  zp.link_regions = true;
  const PlanResult linked = plan(pf.region, cut, ZigzagSpec{zp});
  ASSERT_EQ(alone.status, PlanStatus::Ok);
  ASSERT_EQ(linked.status, PlanStatus::Ok);
  const auto& sa = std::get<ZigzagStats>(alone.stats);
  const auto& sl = std::get<ZigzagStats>(linked.stats);
  EXPECT_EQ(sa.region_links, 0u);
  ASSERT_GE(sl.region_links, 1u) << "the bench pockets' regions meet where the ones before them were cut";
  EXPECT_EQ(linked.path.chains.size() + sl.region_links, alone.path.chains.size());
  EXPECT_EQ(linked.predrill.size(), linked.path.chains.size());

  // Independent raster oracle, away from the band along the walls that the contour pass sweeps
  // anyway (where a region started from another corner walks along other walls, and a link may
  // take a corner next to a region's start): the linked plan cuts what the regions cut on their
  // own, and its links add at most slivers, ≤ kLinkSliverMm2 per link.
  const double R = cut.tool.diameter / 2;
  const std::vector<Vec2> b = flatten(pf.region.boundary, 0.01);
  Vec2 lo = b.front(), hi = b.front();
  for (const Vec2& p : b) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  Raster ras_alone(lo - Vec2(R, R), hi + Vec2(R, R), 0.25), ras_linked = ras_alone;
  for (const Chain& c : alone.path.chains)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) ras_alone.stamp(c.pts[k].p(), c.pts[k + 1].p(), R);
  for (const Chain& c : linked.path.chains)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) ras_linked.stamp(c.pts[k].p(), c.pts[k + 1].p(), R);
  const Clearance walls(pf.region, 0.0);
  std::size_t extra = 0, missing = 0;
  for (long gy = 0; gy < ras_alone.ny; ++gy)
    for (long gx = 0; gx < ras_alone.nx; ++gx) {
      const auto i = static_cast<std::size_t>(gy * ras_alone.nx + gx);
      const Vec2 c(ras_alone.lo.x() + static_cast<double>(gx) * ras_alone.h,
                   ras_alone.lo.y() + static_cast<double>(gy) * ras_alone.h);
      if (walls.wall_distance(c) <= cut.clearance() + R + 0.25) continue;  // the wall band
      if (ras_alone.cut[i] && !ras_linked.cut[i]) ++missing;
      if (ras_linked.cut[i] && !ras_alone.cut[i]) ++extra;
    }
  EXPECT_EQ(missing, 0u) << "the linked plan must cut everything the regions cut on their own";
  EXPECT_LE(static_cast<double>(extra) * ras_alone.h * ras_alone.h,
            (kLinkSliverMm2 + 0.5) * static_cast<double>(sl.region_links))
      << "links cut material away from the walls that no region cuts";

  // Machined: no gouge, one retraction and one entry fewer per link than the regions and the wall
  // loops entered one by one (the programs of before issue 11's links), faster.
  MachiningOptions opt;
  opt.entry = Entry::Helix;
  opt.contour = true;
  opt.link_walls = false;
  const MachiningResult ma = machine_pocket(pf.region, cut, alone, opt);
  opt.link_walls = true;
  const MachiningResult ml = machine_pocket(pf.region, cut, linked, opt);
  ASSERT_EQ(ml.status, PlanStatus::Ok) << ml.message;
  auto rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(ml.program), cut.safe_z);
  millnet::testing::check_gouge(rep, to_replay(pf.region), R);
  EXPECT_EQ(rep.violations, 0) << rep.first_violation;
  EXPECT_LE(ml.metrics.retractions + static_cast<double>(sl.region_links), ma.metrics.retractions);
  EXPECT_LE(ml.metrics.plunges + static_cast<double>(sl.region_links), ma.metrics.plunges);
  EXPECT_LE(ml.metrics.uncut_area_mm2, 2.0);
  EXPECT_LT(ml.metrics.time_kinematic_min, ma.metrics.time_kinematic_min);
}

INSTANTIATE_TEST_SUITE_P(Pockets, ZigzagLinks,
                         ::testing::Values(LinkCase{"eight_islands", PartitionKind::T},
                                           LinkCase{"eight_islands", PartitionKind::I},
                                           LinkCase{"four_islands", PartitionKind::T},
                                           LinkCase{"four_islands", PartitionKind::I}),
                         [](const ::testing::TestParamInfo<LinkCase>& i) {
                           return std::string(i.param.pocket) + (i.param.partition == PartitionKind::T ? "_t" : "_i");
                         });

}  // namespace
