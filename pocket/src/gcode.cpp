// G-code: levels of 2D plans → a gcode::Program (entries resolved) → RS-274 text (gcode::write).
#include "millnet/pocket/gcode.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/gcode/writer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace millnet::pocket {

Entry parse_entry(std::string_view name) {
  if (name == "predrill") return Entry::Predrill;
  if (name == "helix") return Entry::Helix;
  if (name == "ramp") return Entry::Ramp;
  throw Error("gcode: entry must be \"predrill\", \"helix\" or \"ramp\", got \"" + std::string(name) + "\"");
}

std::string_view to_string(Entry e) {
  switch (e) {
    case Entry::Predrill: return "predrill";
    case Entry::Helix: return "helix";
    case Entry::Ramp: return "ramp";
  }
  return "predrill";
}

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kZEps = 1e-9;
/// Decimals of the figures in the program's comments (the coordinates' are the dialect's).
constexpr int kCommentDecimals = 4;

/// One motion while the program is built; comments are attached after the fact (the first move of
/// a level, an entry's first move), so they become Comment items only in to_program.
struct Step {
  gcode::Motion g = gcode::Motion::Rapid;
  std::array<double, 3> to{};
  std::array<double, 2> center{};
  double feed = 0;
  std::string comment;  ///< emitted before the move when not empty
  bool drill = false;   ///< belongs to the pre-drilling operation (op 1)
};

struct Builder {
  const GcodeParams& gp;
  std::vector<Step> moves;
  std::array<double, 3> pos{0, 0, 0};
  bool pos_known = false;

  void rapid(std::optional<double> x, std::optional<double> y, std::optional<double> z, std::string c = {}) {
    Step m;
    m.g = gcode::Motion::Rapid;
    m.to = {x.value_or(pos[0]), y.value_or(pos[1]), z.value_or(pos[2])};
    m.comment = std::move(c);
    push(std::move(m));
  }
  void line(double x, double y, double z, double f) {
    Step m;
    m.g = gcode::Motion::Line;
    m.to = {x, y, z};
    m.feed = f;
    push(std::move(m));
  }
  void arc(bool ccw, const Vec2& c, double x, double y, double z, double f) {
    Step m;
    m.g = ccw ? gcode::Motion::ArcCCW : gcode::Motion::ArcCW;
    m.to = {x, y, z};
    m.center = {c.x(), c.y()};
    m.feed = f;
    push(std::move(m));
  }
  void push(Step m) {
    const bool same = pos_known && m.to == pos;
    if (same && m.comment.empty()) return;  // zero-length moves say nothing
    pos = m.to;
    pos_known = true;
    moves.push_back(std::move(m));
  }
  void retract() {
    if (!pos_known || pos[2] < gp.cut.safe_z - kZEps) rapid(std::nullopt, std::nullopt, gp.cut.safe_z);
  }
  /// Retract, rapid above p, rapid down to approach height above `top` (never above safe Z).
  void go_above(const Vec2& p, double top) {
    const bool here = pos_known && std::hypot(pos[0] - p.x(), pos[1] - p.y()) < 1e-9;
    if (!here) {
      retract();
      rapid(p.x(), p.y(), std::nullopt);
    }
    const double za = approach_z(top);
    if (pos[2] > za + kZEps) rapid(std::nullopt, std::nullopt, za);
  }
  /// The height go_above leaves the tool at over material whose top is `top`.
  [[nodiscard]] double approach_z(double top) const { return std::min(gp.cut.safe_z, top + gp.approach_mm); }
};

/// Helix centre and radius that keep the whole helix of tool centres clear of the walls:
/// radius ≤ 0.45·D, shrunk (and the centre moved round p) until it fits. Empty when none fits.
std::optional<std::pair<Vec2, double>> fit_helix(const Clearance& clear, const Vec2& p, double D) {
  for (double rh = 0.45 * D; rh >= 0.05 * D; rh *= 0.8)
    for (int k = 0; k < 8; ++k) {
      const double a = k * kPi / 4;
      const Vec2 c = p + rh * Vec2(std::cos(a), std::sin(a));
      if (clear.point_ok(c) && clear.wall_distance(c) >= clear.clearance() + rh) return std::make_pair(c, rh);
    }
  return std::nullopt;
}

/// Where a helix round c (radius rh) from z_from to z_to at angle_deg must start so that its
/// descent ends at p (on its circle): sweep = (z_from − z_to) / (rh · tan angle) before it.
Vec2 helix_start(const Vec2& p, const Vec2& c, double rh, double z_from, double z_to, double angle_deg) {
  const double sweep = (z_from - z_to) / (rh * std::tan(angle_deg * kPi / 180));
  const double a = std::atan2(p.y() - c.y(), p.x() - c.x()) - sweep;
  return {c.x() + rh * std::cos(a), c.y() + rh * std::sin(a)};
}

void helix(Builder& b, const Vec2& s, const Vec2& p, const Vec2& c, double rh, double z_from, double z_to, double feed,
           double angle_deg, double flat_feed, double air_feed) {
  // Counter-clockwise (G3) turns descending at exactly the entry angle at the entry feed, from s:
  // half turns, then the part of one that is left (the helix ends where its slope has taken it down,
  // not at the next half turn: until 2026-11-25 the descent was spread over whole half turns, up
  // to half a pitch of ramp more). Then one flat turn at the floor at the cutting feed: it only
  // trims the last pitch's wedge of the ramp (≤ one pitch deep), a light cut, not a ramp into
  // material (at 300 mm/min it was 0.09 of the 0.52 min the bench pockets' helix took).
  // With s = helix_start(p, …) the descent ends at p, where the chain begins, and the flat turn
  // closes there (until 2026-11-26 every helix started at p and its tool went back across the bore
  // from where the descent ended, up to 2·rh).
  const double slope = std::tan(angle_deg * kPi / 180);
  const double sweep = (z_from - z_to) / (rh * slope);  // radians of descent
  const double a0 = std::atan2(s.y() - c.y(), s.x() - c.x());
  const auto at = [&](double a) { return Vec2(c.x() + rh * std::cos(a), c.y() + rh * std::sin(a)); };
  b.line(s.x(), s.y(), z_from, feed);
  const int halves = std::max(1, static_cast<int>(std::ceil(sweep / kPi - 1e-9)));
  Vec2 end = s;
  for (int h = 1; h <= halves; ++h) {
    const double a = h < halves ? h * kPi : sweep;
    end = h < halves ? ((h % 2 == 1) ? Vec2(2 * c - s) : s) : at(a0 + a);
    if (h == halves && (end - p).norm() < 1e-6) end = p;  // it ends at p: exactly there
    b.arc(true, c, end.x(), end.y(), h < halves ? z_from - rh * slope * a : z_to, feed);
  }
  const Vec2 opp = 2 * c - end;
  b.arc(true, c, opp.x(), opp.y(), z_to, flat_feed);
  b.arc(true, c, end.x(), end.y(), z_to, flat_feed);
  // Where it did not end at p (the tool started lower than planned): back to p across the bore (a
  // chord of the circle of centres: all cut, so at the feed of moves through cut material where
  // there is one).
  if ((end - p).norm() > 1e-9) b.line(p.x(), p.y(), z_to, std::max(flat_feed, air_feed));
}

std::string fmt(double v, int decimals) { return gcode::format_number(v, decimals); }

void check_params(const GcodeParams& gp) {
  const CutParams& c = gp.cut;
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v))
      throw Error(std::string("gcode: ") + name + " must be > 0, got " + std::to_string(v));
  };
  positive(c.tool_diameter, "tool_diameter");
  positive(c.safe_z, "safe_z");
  positive(c.feed_half, "feed_half");
  positive(c.feed_plunge, "feed_plunge");
  positive(c.rapid_rate, "rapid_rate");
  positive(gp.entry_angle_deg, "entry_angle_deg");
  if (!(gp.ramp_clearance_mm >= 0) || !std::isfinite(gp.ramp_clearance_mm))
    throw Error("gcode: ramp_clearance_mm must be >= 0, got " + std::to_string(gp.ramp_clearance_mm));
  if (c.spindle_rpm < 0) throw Error("gcode: spindle_rpm must be >= 0");
}
}  // namespace

std::optional<std::pair<Vec2, double>> entry_helix(const Clearance& clear, const Vec2& p, double D) {
  return fit_helix(clear, p, D);
}

std::int64_t level_count(double depth, double step_down) {
  if (!(depth > 0) || !std::isfinite(depth)) throw Error("depth must be > 0, got " + format_double(depth));
  if (!(step_down > 0) || !std::isfinite(step_down))
    throw Error("step_down must be > 0, got " + format_double(step_down));
  const double n = std::ceil(depth / step_down - 1e-9);  // a double first: it may be far beyond any integer
  if (!(n <= static_cast<double>(kMaxLevels)))
    // Names the flag and the key that set it (issue 15; tests/corpus/cli/flag_step_down_1e-9.args).
    throw Error("--step-down / /pocket/step_down: depth " + format_double(depth) + " mm at step-down " +
                format_double(step_down) + " mm makes " + format_double(n) + " Z levels; at most " +
                std::to_string(kMaxLevels) + " (raise the step-down)");
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(n));
}

std::vector<double> level_zs(double depth, double step_down) {
  const std::int64_t n = level_count(depth, step_down);
  std::vector<double> z;
  z.reserve(static_cast<std::size_t>(n));
  for (std::int64_t k = 1; k <= n; ++k) z.push_back(-depth * static_cast<double>(k) / static_cast<double>(n));
  return z;
}

namespace {
std::vector<Step> build_steps(const std::vector<LevelPlan>& levels, const GcodeParams& gp) {
  check_params(gp);
  const CutParams& cut = gp.cut;
  Builder b{gp, {}, {}, false};
  b.rapid(std::nullopt, std::nullopt, cut.safe_z);
  for (const LevelPlan& L : levels)
    if (!(L.z < L.top_z) || L.top_z > kZEps)
      throw Error("gcode: level z " + std::to_string(L.z) + " must lie below its top " + std::to_string(L.top_z) +
                  " and the top at or below Z = 0");

  // 1. Pre-drilling: every distinct predrill point, plain plunges to the deepest level needing it.
  if (gp.entry == Entry::Predrill) {
    std::vector<std::pair<Vec2, double>> holes;  // O(holes²) de-duplication: holes are few
    for (const LevelPlan& L : levels)
      for (const Vec2& p : L.predrill) {
        auto it = std::find_if(holes.begin(), holes.end(), [&](const auto& h) { return (h.first - p).norm() < 1e-6; });
        if (it == holes.end())
          holes.emplace_back(p, L.z);
        else
          it->second = std::min(it->second, L.z);
      }
    for (std::size_t k = 0; k < holes.size(); ++k) {
      const auto& [p, z] = holes[k];
      b.rapid(std::nullopt, std::nullopt, cut.safe_z);
      b.rapid(p.x(), p.y(), std::nullopt, k == 0 ? "pre-drill" : "");
      b.moves.back().drill = true;
      b.rapid(std::nullopt, std::nullopt, std::min(cut.safe_z, gp.approach_mm));
      b.moves.back().drill = true;
      b.line(p.x(), p.y(), z, cut.feed_plunge);
      b.moves.back().drill = true;
      b.rapid(std::nullopt, std::nullopt, cut.safe_z);
      b.moves.back().drill = true;
    }
  }

  // 2. Levels top-down, chains in order.
  for (std::size_t li = 0; li < levels.size(); ++li) {
    const LevelPlan& L = levels[li];
    const double entry_feed = cut.feed_entry > 0 ? cut.feed_entry : cut.feed_plunge;
    std::optional<Clearance> clear;
    if (gp.entry == Entry::Helix || gp.entry == Entry::Ramp) clear.emplace(L.region, cut.clearance());
    bool first = true;
    for (const Chain& ch : L.path.chains) {
      if (ch.pts.empty()) continue;
      const Vec2 p0 = ch.pts.front().p();
      // Entry (below), chosen before the tool goes above its start: a helix starts on its circle
      // so that its descent ends at p0 (helix_start), from the height ramp_start gives.
      const bool rampable = ch.predrill && ch.pts.size() >= 2 && ch.pts[0].bulge == 0.0 &&
                            std::min((ch.pts[1].p() - p0).norm(), 2 * cut.tool_diameter) >= 0.05 * cut.tool_diameter;
      std::optional<std::pair<Vec2, double>> hx;  // fitted only where a helix may be used
      if (ch.predrill && (gp.entry == Entry::Helix || (gp.entry == Entry::Ramp && !rampable)))
        hx = fit_helix(*clear, p0, cut.tool_diameter);
      const bool by_helix = hx.has_value();
      const double z_helix = std::min(b.approach_z(L.top_z), L.top_z + gp.ramp_clearance_mm);
      const Vec2 start = by_helix ? helix_start(p0, hx->first, hx->second, z_helix, L.z, gp.entry_angle_deg) : p0;
      b.go_above(start, L.top_z);
      if (first) {
        b.moves.back().comment = "level " + std::to_string(li + 1) + " of " + std::to_string(levels.size()) + ": Z " +
                                 fmt(L.z, kCommentDecimals);
        first = false;
      }
      // Entry.
      // A ramp along the chain's first (straight) segment: the tool stays on the chain's own
      // footprint, so it sweeps nothing the chain does not. Entry "ramp" tries it first and falls
      // back to a helix; entry "helix" falls back to it where no helix fits (at a wall, where
      // every zigzag pass ends): a plain plunge into uncut material only where neither fits.
      // A helix or ramp starts ramp_clearance_mm above the material top: from approach height the
      // tool feeds straight down to it (at 3° every 0.1 mm of descent is 1.9 mm of ramp at the
      // entry feed; until 2026-11-25 the ramp began at approach height, 1 mm up, 0.09 min an entry).
      const auto ramp_start = [&](double top) {
        const double z = std::min(b.pos[2], top + gp.ramp_clearance_mm);
        if (b.pos[2] > z + kZEps) b.line(b.pos[0], b.pos[1], z, cut.feed_plunge);
        return z;
      };
      const auto try_ramp = [&]() {
        if (!rampable) return false;
        const Vec2 p1 = ch.pts[1].p();
        const double seg = (p1 - p0).norm();
        const double Lr = std::min(seg, 2 * cut.tool_diameter);
        const double z0 = ramp_start(L.top_z);
        const double slope = std::tan(gp.entry_angle_deg * kPi / 180);
        int legs = std::max(2, static_cast<int>(std::ceil((z0 - L.z) / (Lr * slope) - 1e-9)));
        if (legs % 2 == 1) ++legs;  // end back at p0
        // Legs shortened to descend at exactly the entry angle: the ramp is (z0 − z) / tan(angle)
        // long, whatever the rounding to an even number of legs.
        const Vec2 q = p0 + (p1 - p0) * ((z0 - L.z) / (legs * slope) / seg);
        for (int k = 1; k <= legs; ++k) {
          const Vec2& t = (k % 2 == 1) ? q : p0;
          b.line(t.x(), t.y(), z0 - (z0 - L.z) * k / legs, entry_feed);
        }
        b.moves[b.moves.size() - static_cast<std::size_t>(legs)].comment = "ramp entry";
        return true;
      };
      bool helixed = false;  // entered by the helix, its flat turn included
      const auto try_helix = [&]() {
        if (!by_helix) return false;
        helixed = true;
        const std::size_t at = b.moves.size();
        helix(b, start, p0, hx->first, hx->second, ramp_start(L.top_z), L.z, entry_feed, gp.entry_angle_deg,
              std::max(entry_feed, cut.feed_slot > 0 ? cut.feed_slot : cut.feed_half), cut.feed_air);
        if (at < b.moves.size()) b.moves[at].comment = "helix entry, radius " + fmt(hx->second, kCommentDecimals);
        return true;
      };
      bool entered = false;
      if (gp.entry == Entry::Ramp) entered = try_ramp() || try_helix();
      if (gp.entry == Entry::Helix) entered = try_helix() || try_ramp();
      if (!entered) {
        b.line(p0.x(), p0.y(), L.z, cut.feed_plunge);
        if (ch.predrill && gp.entry != Entry::Predrill)
          b.moves.back().comment =
              "WARNING: no room for a " + std::string(to_string(gp.entry)) + " entry: plain plunge";
      }
      // Cut (after a helix, from the end of the chain's own turn round its bore: Chain::entry_turn).
      const std::size_t k0 = helixed ? std::min(ch.entry_turn, ch.pts.size() - 1) : 0;
      for (std::size_t k = k0; k + 1 < ch.pts.size(); ++k) {
        const double f = (k < ch.feed.size() && ch.feed[k] > 0) ? ch.feed[k] : cut.feed_half;
        const Vertex& a = ch.pts[k];
        const Vertex& e = ch.pts[k + 1];
        if (a.bulge == 0.0) {
          b.line(e.x, e.y, L.z, f);
        } else {
          const Arc arc = arc_of(Segment{a.p(), e.p(), a.bulge});
          b.arc(arc.sweep > 0, arc.center, e.x, e.y, L.z, f);
        }
      }
    }
  }
  b.retract();
  return std::move(b.moves);
}

/// Header comments (the parameters) for the program.
std::vector<std::string> header(const std::vector<LevelPlan>& levels, const GcodeParams& gp) {
  const CutParams& c = gp.cut;
  const int d = kCommentDecimals;
  std::vector<std::string> h;
  h.push_back(gp.program_name.empty() ? std::string("millnet pocket") : gp.program_name);
  h.push_back("generated by millnet; units mm; pocket top Z 0, floor Z " + fmt(-c.depth, d));
  h.push_back("tool diameter " + fmt(c.tool_diameter, d) + " stepover " + fmt(c.stepover, d) + " stock to leave " +
              fmt(c.stock_to_leave, d));
  h.push_back("depth " + fmt(c.depth, d) + " step-down " + fmt(c.step_down, d) + " levels " +
              std::to_string(levels.size()) + " safe Z " + fmt(c.safe_z, d));
  h.push_back("feeds: slot f1 " + fmt(c.feed_slot, 1) + " half f2 " + fmt(c.feed_half, 1) + " plunge " +
              fmt(c.feed_plunge, 1) + " limits " + fmt(c.feed_min, 1) + ".." + fmt(c.feed_max, 1) +
              (c.feed_adjust ? " adjusted by feed map" : " constant") +
              (c.feed_air > 0 ? "; moves through cut material " + fmt(c.feed_air, 1) : std::string()) + "; spindle " +
              fmt(c.spindle_rpm, 0) + " rpm");
  for (const std::string& s : c.header) h.push_back(s);
  h.push_back("entry " + std::string(to_string(gp.entry)));
  for (const std::string& s : gp.comments) h.push_back(s);
  return h;
}

/// Steps → items: the drilling operation between "load a drill" and the pause for the end mill,
/// the spindle on before the first milling feed move, off at the end.
gcode::Program to_program(const std::vector<Step>& steps, const GcodeParams& gp) {
  const CutParams& c = gp.cut;
  const int d = kCommentDecimals;
  gcode::Program prog;
  auto& items = prog.items;
  bool spindle_on = false, in_drill = false;
  for (std::size_t k = 0; k < steps.size(); ++k) {  // O(steps)
    const Step& m = steps[k];
    if (m.drill && !in_drill) {
      items.emplace_back(gcode::Comment{"PRE-DRILL: load a drill of diameter " + fmt(c.tool_diameter, d) + " mm"});
      items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, c.spindle_rpm});
      in_drill = true;
    }
    if (!m.drill && in_drill) {
      items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, c.spindle_rpm});
      items.emplace_back(
          gcode::Comment{"change to the end mill of diameter " + fmt(c.tool_diameter, d) + " mm, then resume"});
      items.emplace_back(gcode::Pause{false});
      in_drill = false;
    }
    if (!m.drill && m.g != gcode::Motion::Rapid && !spindle_on) {
      // Spindle on before the first milling feed move (the rapids above it are harmless).
      items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, c.spindle_rpm});
      spindle_on = true;
    }
    if (!m.comment.empty()) items.emplace_back(gcode::Comment{m.comment});
    gcode::Move mv;
    mv.motion = m.g;
    mv.to = m.to;
    mv.center = m.center;
    mv.feed = m.feed;
    mv.axes = k == 0 ? gcode::kZ : gcode::kXYZ;  // the first move sets Z only
    mv.op = m.drill ? 1 : 0;
    items.emplace_back(mv);
  }
  if (in_drill) items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, c.spindle_rpm});
  if (spindle_on) items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, c.spindle_rpm});
  return prog;
}
}  // namespace

gcode::Program build_program(const std::vector<LevelPlan>& levels, const GcodeParams& gp) {
  gcode::Program prog = to_program(build_steps(levels, gp), gp);
  prog.header = header(levels, gp);
  return prog;
}

gcode::StockFrame stock_frame(const CutParams& cut) {
  gcode::StockFrame f;
  f.clearance_z_mm = cut.safe_z;
  f.rapid_mm_min = cut.rapid_rate;
  f.nominal_feed_mm_min = cut.feed_half;
  return f;
}

}  // namespace millnet::pocket
