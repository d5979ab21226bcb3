// G-code writer checked by the independent replay (tests/testing/gcode_replay).
#include "testing/linuxcnc.hpp"
#include "testing/program_text.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/pocket/gcode.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/pocket_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <unistd.h>

using namespace millnet::pocket;
using millnet::testing::ReplayPocket;
using millnet::testing::to_replay;
namespace {
Loop rect(double x0, double y0, double x1, double y1) { return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}; }
/// Two chains in a 60×60 pocket: a line/arc chain and a square, feeds varying.
Path2D sample_path() {
  Path2D p;
  Chain a;
  a.pts = {{10, 10, 0}, {30, 10, std::tan(std::numbers::pi / 8)}, {40, 20, 0}, {40, 40, -0.3}, {20, 45, 0}};
  a.feed = {80, 80, 120, 60};
  Chain b;
  b.pts = {{15, 30, 0}, {25, 30, 0}, {25, 40, 0}, {15, 40, 0}, {15, 30, 0}};
  b.feed = {100, 100, 100, 100};
  b.predrill = false;
  p.chains = {a, b};
  return p;
}
std::vector<LevelPlan> two_levels(const Region& r) {
  std::vector<LevelPlan> L(2);
  L[0].z = -2.5;
  L[0].top_z = 0;
  L[1].z = -5;
  L[1].top_z = -2.5;
  for (LevelPlan& l : L) {
    l.region = r;
    l.path = sample_path();
    l.predrill = {Vec2(10, 10)};
  }
  return L;
}
}  // namespace

TEST(PocketGcode, LevelZs) {
  EXPECT_EQ(level_zs(5, 5), std::vector<double>({-5}));
  EXPECT_EQ(level_zs(5, 10), std::vector<double>({-5}));
  const auto z = level_zs(5, 2);
  ASSERT_EQ(z.size(), 3u);
  EXPECT_NEAR(z[0], -5.0 / 3, 1e-12);
  EXPECT_NEAR(z[2], -5, 1e-12);
  EXPECT_THROW((void)level_zs(0, 1), millnet::Error);
}

TEST(PocketGcode, RoundTripThroughIndependentReplay) {
  const Region r{rect(0, 0, 60, 60), {}};
  GcodeParams gp;
  gp.cut.tool.diameter = 6;
  gp.cut.safe_z = 5;
  const auto levels = two_levels(r);
  const std::string text = millnet::testing::linuxcnc_text(build_program(levels, gp));
  auto rep = millnet::testing::replay_gcode(text, gp.cut.safe_z);
  const double per_level = sample_path().cut_length();
  ASSERT_EQ(rep.cut_length_by_z.size(), 2u);
  for (const auto& [z, len] : rep.cut_length_by_z) EXPECT_NEAR(len, per_level, 1e-3) << "z " << z;
  // Retractions: 2 chains × 2 levels − 1, plus the one out of the pre-drilled hole (the replay
  // does not tell drilling from milling); plunges: 4 milling entries + 1 pre-drilled hole.
  EXPECT_EQ(rep.retractions, 3 + 1);
  EXPECT_EQ(rep.plunges, 5);
  EXPECT_NEAR(rep.min_z, -5, 1e-9);
  EXPECT_TRUE(rep.uses_feed_everywhere);
  millnet::testing::check_gouge(rep, to_replay(r), 3.0);
  EXPECT_EQ(rep.violations, 0) << rep.first_violation;
  // The module's own figures agree with the replay.
  const millnet::gcode::ProgramStats ms = millnet::gcode::stats(build_program(levels, gp), {}, stock_frame(gp.cut));
  EXPECT_NEAR(ms.xy_cut_length_mm, rep.cut_length, 1e-3);
  EXPECT_NEAR(ms.xy_rapid_length_mm, rep.rapid_length, 1e-3);
  EXPECT_EQ(ms.retractions, 3u);
  EXPECT_EQ(ms.entries, 4u);  // milling entries only
  // F only where it changes; header words; no canned cycles; ends with M30.
  std::istringstream in(text);
  std::string line, last_f;
  int f_words = 0;
  while (std::getline(in, line)) {
    EXPECT_EQ(line.find("G8"), std::string::npos) << line;
    const auto p = line.find(" F");
    if (p == std::string::npos || line[0] == '(') continue;
    const std::string f = line.substr(p + 2);
    EXPECT_NE(f, last_f) << "repeated feed word: " << line;
    last_f = f;
    ++f_words;
  }
  EXPECT_GE(f_words, 5);
  EXPECT_NE(text.find("G21 G90 G17 G94"), std::string::npos);
  EXPECT_NE(text.find("M3 S3000"), std::string::npos);
  EXPECT_NE(text.find("PRE-DRILL"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 4), "M30\n");
  // Deterministic bytes.
  EXPECT_EQ(text, millnet::testing::linuxcnc_text(build_program(levels, gp)));
}

namespace {
/// One level at Z −5 of region r with a single chain (entering uncut material).
std::vector<LevelPlan> one_chain_at_z5(const Region& r, std::vector<Vertex> pts) {
  std::vector<LevelPlan> L(1);
  L[0].z = -5;
  L[0].region = r;
  Chain c;
  c.pts = std::move(pts);
  L[0].path.chains = {c};
  return L;
}
}  // namespace

TEST(PocketGcode, HelixAndRampEntriesStayClear) {
  // A tight pocket: 14 mm wide, tool Ø10: the helix must shrink to fit (clearance 5, room 2 mm).
  const Region r{rect(0, 0, 60, 14), {}};
  for (const char* entry : {"helix", "ramp"}) {
    GcodeParams gp;
    gp.entry = parse_entry(entry);
    gp.cut.tool.diameter = 10;
    const std::string text =
        millnet::testing::linuxcnc_text(build_program(one_chain_at_z5(r, {{10, 7, 0}, {50, 7, 0}}), gp));
    auto rep = millnet::testing::replay_gcode(text, gp.cut.safe_z);
    millnet::testing::check_gouge(rep, to_replay(r), 5.0);
    EXPECT_EQ(rep.violations, 0) << entry << ": " << rep.first_violation;
    EXPECT_NE(text.find(std::string(entry) + " entry"), std::string::npos) << text;
    EXPECT_EQ(text.find("PRE-DRILL"), std::string::npos);
    EXPECT_NEAR(rep.min_z, -5, 1e-9);
    // The entry descends gradually: no feed move drops more than pitch/2 (helix) or one ramp leg.
    for (const auto& m : rep.moves) {
      if (m.g != 0 && m.from[2] < 0.5) {
        EXPECT_LT(m.from[2] - m.to[2], 2.5) << entry << " line " << m.line;
      }
    }
  }
}

TEST(PocketGcode, HelixDescendsAtTheEntryFeedAndTrimsItsFloorAtTheSlotFeed) {
  // Issue 11's setting: ramps at 300 mm/min, cutting at 1500. The tool feeds straight down from
  // approach height (1 mm) to ramp_clearance (0.2 mm) above the stock; every descending move of the
  // helix is at the entry feed and at exactly the entry angle; the flat turn at the floor (two half
  // turns, no descent) at the slot feed.
  const Region r{rect(0, 0, 60, 40), {}};
  GcodeParams gp;
  gp.entry = Entry::Helix;
  gp.cut.tool.diameter = 10;
  gp.cut.feed_slot = gp.cut.feed_half = 1500;
  gp.cut.feed_plunge = 300;
  // Horizontal length of an arc move (counter-clockwise, G3), from its centre.
  const auto arc_xy = [](const millnet::testing::ReplayMove& m) {
    const double r0 = std::hypot(m.from[0] - m.center[0], m.from[1] - m.center[1]);
    double a = std::atan2(m.to[1] - m.center[1], m.to[0] - m.center[0]) -
               std::atan2(m.from[1] - m.center[1], m.from[0] - m.center[0]);
    while (a <= 1e-12) a += 2 * std::numbers::pi;
    return r0 * a;
  };
  const auto check = [&](double angle_deg, int want_descending, double want_ramp_xy) {
    gp.entry_angle_deg = angle_deg;
    const auto rep = millnet::testing::replay_gcode(
        millnet::testing::linuxcnc_text(build_program(one_chain_at_z5(r, {{30, 20, 0}, {45, 20, 0}}), gp)),
        gp.cut.safe_z);
    int descending = 0, flat = 0, straight_down = 0;
    double ramp_xy = 0;
    for (const auto& m : rep.moves) {
      if (m.g == 1 && m.to[2] < m.from[2] - 1e-9) {
        ++straight_down;  // approach height to the ramp's start, through air
        EXPECT_NEAR(m.from[2], 1, 1e-9);
        EXPECT_NEAR(m.to[2], 0.2, 1e-9);
        EXPECT_DOUBLE_EQ(m.feed, 300) << "line " << m.line;
      }
      if (m.g != 2 && m.g != 3) continue;
      if (m.to[2] < m.from[2] - 1e-9) {
        ++descending;
        ramp_xy += arc_xy(m);
        EXPECT_DOUBLE_EQ(m.feed, 300) << "line " << m.line;
        // The slope of every arc is the entry angle's (4-decimal coordinates: within 2e-4).
        EXPECT_NEAR((m.from[2] - m.to[2]) / arc_xy(m), std::tan(angle_deg * std::numbers::pi / 180), 2e-4)
            << "line " << m.line;
      } else {
        ++flat;
        EXPECT_NEAR(m.to[2], -5, 1e-9) << "line " << m.line;
        EXPECT_DOUBLE_EQ(m.feed, 1500) << "line " << m.line;
      }
    }
    EXPECT_EQ(straight_down, 1) << angle_deg;
    EXPECT_EQ(descending, want_descending) << angle_deg;
    EXPECT_EQ(flat, 2) << angle_deg;
    EXPECT_NEAR(ramp_xy, want_ramp_xy, 0.01) << angle_deg;
  };
  // From 0.2 mm above the stock to −5 at 3°, radius 4.5: 5.2 / tan 3° = 99.22 mm of ramp, a half
  // turn π·4.5 = 14.137 mm, so 7.018 half turns: 7 and a short arc (until 2026-11-25: from 1 mm up,
  // ⌈6 / 0.741⌉ = 9 whole half turns, 127.2 mm).
  check(3, 8, 99.222);
  // /pocket/entry_angle 5°: 5.2 / tan 5° = 59.436 mm = 4.204 half turns: 5 arcs.
  check(5, 5, 59.436);
}

TEST(PocketGcode, HelixEndsWhereTheChainBeginsAndSkipsTheChainsOwnTurnRoundIt) {
  // The helix starts on its circle so that its descent ends at the chain's start, where its flat
  // turn closes: no move back across the bore (until 2026-11-26 one of up to 2·rh). A chain whose
  // first moves are a turn round that bore (Chain::entry_turn, the adaptive planner's) skips them
  // after a helix, whose own flat turn cut the bore; entered any other way, it cuts them.
  const Region r{rect(0, 0, 60, 40), {}};
  const Vec2 p0(30, 20);
  const auto hx = entry_helix(Clearance(r, 5), p0, 10);
  ASSERT_TRUE(hx.has_value());
  std::vector<Vertex> pts{{p0.x(), p0.y(), 0}};
  for (int k = 1; k <= 8; ++k) {
    const double a = 2 * std::numbers::pi * k / 8;
    const Vec2 v = p0 - hx->first;
    const Vec2 q =
        hx->first + Vec2(std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y());
    pts.push_back({q.x(), q.y(), 0});
  }
  pts.push_back({45, 20, 0});
  auto levels = one_chain_at_z5(r, pts);
  levels[0].path.chains[0].entry_turn = 8;
  GcodeParams gp;
  gp.cut.tool.diameter = 10;
  gp.cut.feed_slot = gp.cut.feed_half = 1500;
  gp.cut.feed_plunge = 300;
  gp.cut.feed_air = 4800;
  const auto replay = [&](Entry e) {
    gp.entry = e;
    return millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(build_program(levels, gp)), gp.cut.safe_z);
  };
  const auto floor_lines = [](const millnet::testing::ReplayResult& rep) {
    std::vector<millnet::testing::ReplayMove> out;
    for (const auto& m : rep.moves)
      if (m.g == 1 && std::abs(m.from[2] + 5) < 1e-9 && std::abs(m.to[2] + 5) < 1e-9) out.push_back(m);
    return out;
  };
  const auto rep = replay(Entry::Helix);
  const auto lines = floor_lines(rep);
  ASSERT_EQ(lines.size(), 1u);  // the pass only: no chord back, no turn of the chain's own
  EXPECT_NEAR(lines[0].from[0], 30, 1e-9);
  EXPECT_NEAR(lines[0].from[1], 20, 1e-9);
  EXPECT_NEAR(lines[0].to[0], 45, 1e-9);
  EXPECT_DOUBLE_EQ(lines[0].feed, 1500);
  // The descent starts on the helix's circle (the tool feeds down there from approach height).
  for (const auto& m : rep.moves)
    if (m.g == 1 && m.to[2] < m.from[2] - 1e-9 && m.from[2] > 0.5) {
      EXPECT_NEAR(std::hypot(m.to[0] - hx->first.x(), m.to[1] - hx->first.y()), hx->second, 1e-3);
      EXPECT_GT(std::hypot(m.to[0] - 30, m.to[1] - 20), 1.0);  // not at p0: 7.02 half turns before it
    }
  EXPECT_EQ(floor_lines(replay(Entry::Predrill)).size(), 9u);  // plunged: the 8 moves of the turn cut the bore
}

TEST(PocketGcode, BadParameters) {
  EXPECT_THROW((void)parse_entry("drill"), millnet::Error);
  EXPECT_EQ(parse_entry("ramp"), Entry::Ramp);
  EXPECT_EQ(to_string(Entry::Helix), "helix");
  GcodeParams gp;
  gp.cut.feed_plunge = 0;
  EXPECT_THROW((void)build_program({}, gp), millnet::Error);
  GcodeParams ok;
  std::vector<LevelPlan> L(1);
  L[0].z = 1;  // above the top
  EXPECT_THROW((void)build_program(L, ok), millnet::Error);
}

TEST(PocketGcode, ProgramsReadBackAndLinuxcncAcceptsThem) {
  const Region r{rect(0, 0, 60, 60), {}};
  for (Entry e : {Entry::Predrill, Entry::Helix, Entry::Ramp}) {
    GcodeParams gp;
    gp.entry = e;
    gp.cut.tool.diameter = 6;
    gp.cut.safe_z = 5;
    const millnet::gcode::Program prog = build_program(two_levels(r), gp);
    const std::string text = millnet::testing::linuxcnc_text(prog);
    // The one reader gives back the program the writer wrote: same text, same figures.
    const millnet::gcode::Program back = millnet::gcode::read(text, "pocket.nc");
    EXPECT_EQ(millnet::testing::linuxcnc_text(back), text) << to_string(e);
    const millnet::gcode::ProgramStats a = millnet::gcode::stats(prog, {}, stock_frame(gp.cut));
    const millnet::gcode::ProgramStats b = millnet::gcode::stats(back, {}, stock_frame(gp.cut));
    EXPECT_NEAR(a.xy_cut_length_mm, b.xy_cut_length_mm, 1e-3);
    // The text does not mark the pre-drilling operation (op 1), so read back its one hole counts
    // as one more milling plunge.
    EXPECT_EQ(b.entries, a.entries + (e == Entry::Predrill ? 1u : 0u));
    if (!std::filesystem::exists("/usr/bin/rs274")) continue;
    const auto f = std::filesystem::temp_directory_path() /
                   ("millnet_pocket_rs274_" + std::to_string(::getpid()) + std::string(to_string(e)) + ".nc");
    millnet::write_file_atomic(f, text);
    EXPECT_EQ(millnet::testing::linuxcnc_status(f.string()), 0) << to_string(e);
    std::filesystem::remove(f);
  }
}

// Issue 15: `--depth 1e11` or `--step-down 1e-9` overflowed the level count (an int) into
// "levels 1" and one plunge to the floor. Counted in 64 bits and bounded before use.
TEST(PocketGcode, LevelCountIsBoundedBeforeUse) {
  EXPECT_EQ(level_count(5, 2), 3);
  EXPECT_EQ(level_count(5, 10), 1);
  EXPECT_EQ(level_count(10000, 1), 10000);
  for (const auto& [depth, step] : {std::pair{1e11, 5.0}, std::pair{5.0, 1e-9}, std::pair{1e308, 1e-308}}) {
    try {
      (void)level_zs(depth, step);
      FAIL() << depth << " / " << step << " accepted";
    } catch (const millnet::Error& e) {
      EXPECT_NE(std::string(e.what()).find("Z levels; at most 10000"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)level_count(std::nan(""), 1), millnet::Error);
  EXPECT_THROW((void)level_count(5, std::nan("")), millnet::Error);
}
