// Zigzag regions joined with the tool down (ZigzagParams::link_regions, issue 11): against the same
// plan without links, every link saves one retraction and one entry, the G-code never gouges
// (independent replay), and an independent raster oracle finds each link running through material
// the regions before it already cut.
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
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
        if (std::hypot(lo.x() + gx * h - c.x(), lo.y() + gy * h - c.y()) <= r) f(gy * nx + gx);
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

using Seg = std::pair<std::pair<double, double>, std::pair<double, double>>;
Seg key(const Vec2& a, const Vec2& b) {
  auto k = [](const Vec2& p) { return std::pair{std::round(p.x() * 1e6) / 1e6, std::round(p.y() * 1e6) / 1e6}; };
  return k(a) < k(b) ? Seg{k(a), k(b)} : Seg{k(b), k(a)};
}

class ZigzagLinks : public ::testing::TestWithParam<PartitionKind> {};

TEST_P(ZigzagLinks, RegionsJoinedThroughCutMaterialSaveARetractionAndAnEntryEach) {
  const PocketFile pf = read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/eight_islands.json");
  const CutParams cut = bench_cut();
  ZigzagParams zp;
  zp.angle_deg = std::nullopt;
  zp.partition = GetParam();
  zp.link_regions = false;
  const PlanResult alone = plan(pf.region, cut, ZigzagSpec{zp});
  zp.link_regions = true;
  const PlanResult linked = plan(pf.region, cut, ZigzagSpec{zp});
  ASSERT_EQ(alone.status, PlanStatus::Ok);
  ASSERT_EQ(linked.status, PlanStatus::Ok);
  const auto& sa = std::get<ZigzagStats>(alone.stats);
  const auto& sl = std::get<ZigzagStats>(linked.stats);
  EXPECT_EQ(sa.region_links, 0u);
  ASSERT_GE(sl.region_links, 1u) << "eight_islands has regions that a straight move through cut material joins";
  EXPECT_EQ(linked.path.chains.size() + sl.region_links, alone.path.chains.size());
  EXPECT_EQ(linked.predrill.size(), linked.path.chains.size());

  // The same passes: every segment of the unlinked plan is in the linked one; the linked plan's
  // other segments are exactly the links.
  std::set<Seg> passes;
  for (const Chain& c : alone.path.chains)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) passes.insert(key(c.pts[k].p(), c.pts[k + 1].p()));
  const double R = cut.tool_diameter / 2;
  const std::vector<Vec2> b = flatten(pf.region.boundary, 0.01);
  Vec2 lo = b.front(), hi = b.front();
  for (const Vec2& p : b) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  Raster ras(lo - Vec2(R, R), hi + Vec2(R, R), 0.25);
  std::size_t links_seen = 0, seen_passes = 0;
  for (const Chain& c : linked.path.chains)
    for (std::size_t k = 0; k + 1 < c.pts.size(); ++k) {
      const Vec2 p = c.pts[k].p(), q = c.pts[k + 1].p();
      if (passes.count(key(p, q))) {
        ++seen_passes;
      } else {
        // A link: its disk (a hair inside the tool) sweeps nothing uncut except beside its end,
        // where the next region's first pass engages anyway (the tool's disk there).
        ++links_seen;
        std::set<long> fresh;
        ras.segment_cells(p, q, R - 0.1, [&](long cell) {
          if (!ras.cut[static_cast<std::size_t>(cell)]) fresh.insert(cell);
        });
        ras.disk_cells(q, R + 0.1, [&](long cell) { fresh.erase(cell); });
        EXPECT_LE(static_cast<double>(fresh.size()) * ras.h * ras.h, kLinkNewMaterialMm2 + 0.5)
            << "link " << links_seen << " from (" << p.x() << ", " << p.y() << ") to (" << q.x() << ", " << q.y()
            << ") cuts uncut material";
      }
      ras.stamp(p, q, R);
    }
  EXPECT_EQ(links_seen, sl.region_links);
  EXPECT_EQ(seen_passes, passes.size());

  // Machined: no gouge, one retraction and one entry fewer per link.
  MachiningOptions opt;
  opt.entry = Entry::Helix;
  opt.contour = true;
  const MachiningResult ma = machine_pocket(pf.region, cut, alone, opt);
  const MachiningResult ml = machine_pocket(pf.region, cut, linked, opt);
  ASSERT_EQ(ml.status, PlanStatus::Ok) << ml.message;
  auto rep = millnet::testing::replay_gcode(ml.gcode, cut.safe_z);
  millnet::testing::check_gouge(rep, to_replay(pf.region), R);
  EXPECT_EQ(rep.violations, 0) << rep.first_violation;
  EXPECT_EQ(ml.metrics.retractions + static_cast<double>(sl.region_links), ma.metrics.retractions);
  EXPECT_EQ(ml.metrics.plunges + static_cast<double>(sl.region_links), ma.metrics.plunges);
  EXPECT_LE(ml.metrics.uncut_area_mm2, 2.0);
  EXPECT_LT(ml.metrics.time_kinematic_min, ma.metrics.time_kinematic_min);
}

INSTANTIATE_TEST_SUITE_P(Partitions, ZigzagLinks, ::testing::Values(PartitionKind::T, PartitionKind::I));

}  // namespace
