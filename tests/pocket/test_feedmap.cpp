// Feed map: eq. 9 on the seed's numbers and engagement measured on simple cuts.
#include "millnet/pocket/feedmap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <algorithm>

using namespace millnet::pocket;
namespace {
Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }
CutParams seed_params() {
  CutParams c;
  c.tool.diameter = 40;
  c.feed_grid = 4;
  c.stepover = 20;
  c.feed_slot = 50;
  c.feed_half = 100;
  c.feed_min = 10;
  c.feed_max = 500;
  return c;
}
Chain line_chain(Vec2 a, Vec2 b) {
  Chain c;
  c.pts = {{a.x(), a.y(), 0}, {b.x(), b.y(), 0}};
  return c;
}
double median_engagement(const FeedProfile& p, std::size_t chain) {
  std::vector<double> e;
  for (const FeedPiece& q : p.pieces)
    if (q.chain == chain) e.push_back(q.engagement);
  std::sort(e.begin(), e.end());
  return e.at(e.size() / 2);
}
}  // namespace

TEST(PocketFeedMap, SeedExampleEquation9) {
  const CutParams c = seed_params();
  // D = 40, grid 4 ⇒ n1 = 10, n2 = 5; f1 = 50, f2 = 100 (Shin & Suh §6.3).
  EXPECT_DOUBLE_EQ(feed_for_engagement(10, 10, 5, c), 50);
  EXPECT_DOUBLE_EQ(feed_for_engagement(5, 10, 5, c), 100);
  EXPECT_DOUBLE_EQ(feed_for_engagement(4, 10, 5, c), 110);
  CutParams lim = c;
  lim.feed_max = 120;
  lim.feed_min = 60;
  EXPECT_DOUBLE_EQ(feed_for_engagement(0, 10, 5, lim), 120);  // 150 clamped
  EXPECT_DOUBLE_EQ(feed_for_engagement(10, 10, 5, lim), 60);  // 50 clamped
}

TEST(PocketFeedMap, ChipThinningRaisesTheFeedBelowHalfEngagement) {
  CutParams c = seed_params();  // D = 40, n1 = 10, n2 = 5, f1 = 50, f2 = 100
  c.max_chip_thinning = 3;
  c.feed_max = 1000;
  // a_e = D·n3/n1: n3 = 1 ⇒ a_e = 4 mm = 10 % of D ⇒ RCTF = 1/(2·√(0.1·0.9)) = 5/3.
  EXPECT_NEAR(feed_for_engagement(1, 10, 5, c), 100 * 5.0 / 3.0, 1e-9);
  // n3 = 2.5 ⇒ a_e = 25 % ⇒ RCTF = 1/(2·√(0.25·0.75)) = 1.1547.
  EXPECT_NEAR(feed_for_engagement(2.5, 10, 5, c), 100 / (2 * std::sqrt(0.25 * 0.75)), 1e-9);
  // At and above half engagement eq. 9 as before; no engagement: the cap (3 × f2), then feed_max.
  EXPECT_DOUBLE_EQ(feed_for_engagement(5, 10, 5, c), 100);
  EXPECT_DOUBLE_EQ(feed_for_engagement(10, 10, 5, c), 50);
  EXPECT_DOUBLE_EQ(feed_for_engagement(7.5, 10, 5, c), 75);
  EXPECT_DOUBLE_EQ(feed_for_engagement(0, 10, 5, c), 300);
  c.feed_max = 250;
  EXPECT_DOUBLE_EQ(feed_for_engagement(0, 10, 5, c), 250);
}

TEST(PocketFeedMap, SlotThenHalfSlotThenAirCut) {
  const CutParams c = seed_params();
  const Region r{rect(0, 0, 400, 400), {}};
  Path2D p;
  p.chains.push_back(line_chain({100, 100}, {300, 100}));  // full slot
  p.chains.push_back(line_chain({100, 120}, {300, 120}));  // next to it at R: half engaged
  p.chains.push_back(line_chain({100, 110}, {300, 110}));  // already cut: air
  const FeedProfile prof = assign_feeds(p, r, c, 1.0);
  EXPECT_DOUBLE_EQ(prof.n1, 10);
  EXPECT_DOUBLE_EQ(prof.n2, 5);
  // The 200 mm segments were split into stepover (20 mm) pieces, geometry unchanged.
  EXPECT_EQ(p.chains[0].pts.size(), 11u);
  EXPECT_NEAR(p.cut_length(), 600, 1e-9);
  EXPECT_NEAR(median_engagement(prof, 0), 10, 1.0);
  EXPECT_NEAR(median_engagement(prof, 1), 5, 1.0);
  EXPECT_NEAR(median_engagement(prof, 2), 0, 1e-12);
  // Feeds: the slot near f1, the half slot near f2, the air cut at the f_max clamp (eq. 9 → 150).
  EXPECT_NEAR(p.chains[0].feed[5], 50, 10);
  EXPECT_NEAR(p.chains[1].feed[5], 100, 10);
  EXPECT_DOUBLE_EQ(p.chains[2].feed[5], 150);
  for (const FeedPiece& q : prof.pieces) EXPECT_NEAR(q.mrr_mm3_min, q.feed * q.width_mm * 1.0, 1e-9);
}

TEST(PocketFeedMap, MovesThroughCutMaterialRunAtTheAirFeedWhateverFeedAdjustSays) {
  // CutParams::feed_air (issue 11, /pocket/air_feed): the pieces that cut no cell get it, the
  // others keep theirs; with feed adjustment on or off.
  for (const bool adjust : {true, false}) {
    CutParams c = seed_params();
    c.feed_adjust = adjust;
    c.feed_air = 480;
    const Region r{rect(0, 0, 400, 400), {}};
    Path2D p;
    p.chains.push_back(line_chain({100, 100}, {300, 100}));  // a slot
    p.chains.push_back(line_chain({300, 100}, {100, 100}));  // back along it: nothing left to cut
    p.chains.push_back(line_chain({100, 104}, {300, 104}));  // beside it: a 4 mm cut
    (void)assign_feeds(p, r, c, 1.0);
    for (double f : p.chains[1].feed) EXPECT_DOUBLE_EQ(f, 480) << adjust;
    for (const std::size_t ci : {std::size_t{0}, std::size_t{2}})
      for (double f : p.chains[ci].feed) EXPECT_LT(f, 480) << adjust << " chain " << ci;
    // Off (0): the air pieces keep the cutting feed (eq. 9 at n3 = 0, or f2).
    c.feed_air = 0;
    Path2D q;
    q.chains.push_back(line_chain({100, 100}, {300, 100}));
    q.chains.push_back(line_chain({300, 100}, {100, 100}));
    (void)assign_feeds(q, r, c, 1.0);
    for (double f : q.chains[1].feed) EXPECT_DOUBLE_EQ(f, adjust ? feed_for_engagement(0, 10, 5, c) : c.feed_half);
  }
}

TEST(PocketFeedMap, CellsOutsideTheRegionHoldNoMaterial) {
  // The tool runs along the bottom wall line: half of its disk is outside the region ⇒ n3 ≈ R/grid.
  const CutParams c = seed_params();
  const Region r{rect(0, 100, 400, 400), {}};
  Path2D p;
  p.chains.push_back(line_chain({100, 100}, {300, 100}));
  const FeedProfile prof = assign_feeds(p, r, c, 1.0);
  EXPECT_NEAR(median_engagement(prof, 0), 5, 1.0);
  // Constant feed when adjustment is off, profile still measured.
  CutParams off = c;
  off.feed_adjust = false;
  Path2D q;
  q.chains.push_back(line_chain({100, 200}, {300, 200}));
  const FeedProfile prof2 = assign_feeds(q, r, off, 1.0);
  for (double f : q.chains[0].feed) EXPECT_EQ(f, 100);
  EXPECT_NEAR(median_engagement(prof2, 0), 10, 1.0);
}

TEST(PocketFeedMap, ShortStepsArePooledSoARoundingCellDoesNotReadAsASlot) {
  // A half-engaged cut (beside a slot, at R) written as 0.4 mm segments (a tenth of the 4 mm cell).
  // Alone, a step reads 0 or one new column of cells scaled ×10 (a slot, n₁ = 10); pooled over a
  // cell of travel, every piece reads the half slot it is (n₂ = 5).
  const Region r{rect(0, 0, 400, 400), {}};
  auto run = [&](bool pool) {
    CutParams c = seed_params();
    c.feed_pool_short_steps = pool;
    Path2D p;
    p.chains.push_back(line_chain({100, 100}, {300, 100}));  // the slot
    Chain fine;
    for (int k = 0; k <= 500; ++k) fine.pts.push_back({100 + 0.4 * k, 120, 0});
    p.chains.push_back(fine);
    const FeedProfile prof = assign_feeds(p, r, c, 1.0);
    double hi = 0;
    for (const FeedPiece& q : prof.pieces)
      if (q.chain == 1 && q.s_mm > 200 + 20) hi = std::max(hi, q.engagement);  // past the entry
    return hi;
  };
  // n₂ = 5 give or take the crescent's front: a window of one cell of travel gets the cells of the
  // curved front unevenly (3 to 7 here, as a whole-cell step of a long segment does).
  EXPECT_LE(run(true), 7.5);
  EXPECT_GE(run(true), 3.0);
  EXPECT_GE(run(false), 9.9);  // the artifact the pooling removes (kept for the 1995 preset)
}

// The swept width (what max_engagement_deg reads) against hand-computed cuts, at the bench's D/40
// grid, for lines at several angles and sub-cell offsets: a slot sweeps D, a parallel pass R to
// the side of it sweeps R, one 2 mm further sweeps 2 mm (each read away from the passes' ends). The
// centre count n₃ of the same pieces strays by whole cells depending on where the centres fall;
// the swept width stays within kTol of the area (0.15 mm measured; the centre count of the R pass
// reads 5.00–6.75 mm).
TEST(PocketFeedMap, SweptWidthReadsTheCutAreaWhereverTheCellCentresFall) {
  constexpr double kTol = 0.2;  // mm of width: ≈ 2.3° at 90° on Ø10
  CutParams c;
  c.tool.diameter = 10;
  c.feed_grid = 0.25;
  c.stepover = 5;
  c.feed_slot = c.feed_half = c.feed_min = c.feed_max = 1000;
  const Region r{rect(-100, -100, 100, 100), {}};
  double worst = 0, n3_spread_lo = 1e9, n3_spread_hi = 0;
  for (const double deg : {0.0, 17.0, 45.0, 73.0})
    for (const double off : {0.0, 0.05, 0.11, 0.17, 0.23}) {
      const Vec2 u(std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180)), n(-u.y(), u.x());
      const Vec2 a = Vec2(-30, -30 + off) + Vec2(off, 0), b = a + 60 * u;
      Path2D p;
      p.chains.push_back(line_chain(a, b));                  // slot: D
      p.chains.push_back(line_chain(a + 5 * n, b + 5 * n));  // beside it at R: R
      p.chains.push_back(line_chain(a + 7 * n, b + 7 * n));  // 2 mm further: 2
      const FeedProfile prof = assign_feeds(p, r, c, 1.0);
      const double expect[3] = {10, 5, 2};
      double start[3] = {1e18, 1e18, 1e18};  // s_mm runs on over the chains
      for (const FeedPiece& q : prof.pieces) start[q.chain] = std::min(start[q.chain], q.s_mm);
      for (const FeedPiece& q : prof.pieces) {
        const double s0 = q.s_mm - start[q.chain];
        if (s0 < 6 || s0 + q.length_mm > 54) continue;  // away from the ends
        const double e = expect[q.chain];
        worst = std::max(worst, std::abs(q.swept_width_mm - e));
        EXPECT_NEAR(q.swept_width_mm, e, kTol) << deg << "° offset " << off << " chain " << q.chain << " s " << q.s_mm;
        if (q.chain == 1) {
          n3_spread_lo = std::min(n3_spread_lo, q.width_mm);
          n3_spread_hi = std::max(n3_spread_hi, q.width_mm);
        }
      }
    }
  std::printf("[ feed map ] swept width within %.3f mm of the area; centre-count width of the R pass %.2f..%.2f mm\n",
              worst, n3_spread_lo, n3_spread_hi);
}
