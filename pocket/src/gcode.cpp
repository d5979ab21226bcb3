// G-code: levels of 2D plans → a gcode::Program (entries resolved) → RS-274 text (gcode::write).
#include "millnet/pocket/gcode.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/pocket/tolerances.hpp"

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
constexpr double kGcodePi = std::numbers::pi;
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
    const bool here = pos_known && std::hypot(pos[0] - p.x(), pos[1] - p.y()) < tol::coincident_mm;
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
      const double a = k * kGcodePi / 4;
      const Vec2 c = p + rh * Vec2(std::cos(a), std::sin(a));
      if (clear.point_ok(c) && clear.wall_distance(c) >= clear.clearance() + rh) return std::make_pair(c, rh);
    }
  return std::nullopt;
}

/// Where a helix round c (radius rh) from z_from to z_to at angle_deg must start so that its
/// descent ends at p (on its circle): sweep = (z_from − z_to) / (rh · tan angle) before it.
Vec2 helix_start(const Vec2& p, const Vec2& c, double rh, double z_from, double z_to, double angle_deg) {
  const double sweep = (z_from - z_to) / (rh * std::tan(angle_deg * kGcodePi / 180));
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
  const double slope = std::tan(angle_deg * kGcodePi / 180);
  const double sweep = (z_from - z_to) / (rh * slope);  // radians of descent
  const double a0 = std::atan2(s.y() - c.y(), s.x() - c.x());
  const auto at = [&](double a) { return Vec2(c.x() + rh * std::cos(a), c.y() + rh * std::sin(a)); };
  b.line(s.x(), s.y(), z_from, feed);
  const int halves = std::max(1, static_cast<int>(std::ceil(sweep / kGcodePi - 1e-9)));
  Vec2 end = s;
  for (int h = 1; h <= halves; ++h) {
    const double a = h < halves ? h * kGcodePi : sweep;
    end = h < halves ? ((h % 2 == 1) ? Vec2(2 * c - s) : s) : at(a0 + a);
    if (h == halves && (end - p).norm() < tol::join_mm) end = p;  // it ends at p: exactly there
    b.arc(true, c, end.x(), end.y(), h < halves ? z_from - rh * slope * a : z_to, feed);
  }
  const Vec2 opp = 2 * c - end;
  b.arc(true, c, opp.x(), opp.y(), z_to, flat_feed);
  b.arc(true, c, end.x(), end.y(), z_to, flat_feed);
  // Where it did not end at p (the tool started lower than planned): back to p across the bore (a
  // chord of the circle of centres: all cut, so at the feed of moves through cut material where
  // there is one).
  if ((end - p).norm() > tol::coincident_mm) b.line(p.x(), p.y(), z_to, std::max(flat_feed, air_feed));
}

std::string fmt(double v, int decimals) { return gcode::format_number(v, decimals); }

void check_gcode_params(const GcodeParams& gp) {
  const CutParams& c = gp.cut;
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v))
      throw Error(std::string("gcode: ") + name + " must be > 0, got " + std::to_string(v));
  };
  positive(c.tool.diameter, "tool_diameter");
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
void check_levels(const std::vector<LevelPlan>& levels) {
  for (const LevelPlan& L : levels)
    if (!(L.z < L.top_z) || L.top_z > kZEps)
      throw Error("gcode: level z " + std::to_string(L.z) + " must lie below its top " + std::to_string(L.top_z) +
                  " and the top at or below Z = 0");
}

/// Pre-drilling: every distinct predrill point, plain plunges to the deepest level needing it.
void predrill_holes(Builder& b, const std::vector<LevelPlan>& levels) {
  const CutParams& cut = b.gp.cut;
  std::vector<std::pair<Vec2, double>> holes;  // O(holes²) de-duplication: holes are few
  for (const LevelPlan& L : levels)
    for (const Vec2& p : L.predrill) {
      auto it =
          std::find_if(holes.begin(), holes.end(), [&](const auto& h) { return (h.first - p).norm() < tol::join_mm; });
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
    b.rapid(std::nullopt, std::nullopt, std::min(cut.safe_z, b.gp.approach_mm));
    b.moves.back().drill = true;
    b.line(p.x(), p.y(), z, cut.feed_plunge);
    b.moves.back().drill = true;
    b.rapid(std::nullopt, std::nullopt, cut.safe_z);
    b.moves.back().drill = true;
  }
}

/// How a chain will be entered, chosen before the tool goes above its start: a helix starts on its
/// circle so that its descent ends at p0 (helix_start), from the height ramp_start gives.
struct EntryPlan {
  Vec2 p0;                                    ///< the chain's first point
  bool rampable = false;                      ///< a ramp along its first (straight) segment fits
  std::optional<std::pair<Vec2, double>> hx;  ///< the helix, fitted only where one may be used
  Vec2 start;                                 ///< where the tool goes above the material first
};

EntryPlan plan_entry(const Builder& b, const LevelPlan& L, const Chain& ch, const std::optional<Clearance>& clear) {
  const GcodeParams& gp = b.gp;
  const CutParams& cut = gp.cut;
  EntryPlan e;
  e.p0 = ch.pts.front().p();
  e.rampable = ch.predrill && ch.pts.size() >= 2 && ch.pts[0].bulge == 0.0 &&
               std::min((ch.pts[1].p() - e.p0).norm(), 2 * cut.tool.diameter) >= 0.05 * cut.tool.diameter;
  if (ch.predrill && (gp.entry == Entry::Helix || (gp.entry == Entry::Ramp && !e.rampable)))
    e.hx = fit_helix(*clear, e.p0, cut.tool.diameter);
  const double z_helix = std::min(b.approach_z(L.top_z), L.top_z + gp.ramp_clearance_mm);
  e.start = e.hx ? helix_start(e.p0, e.hx->first, e.hx->second, z_helix, L.z, gp.entry_angle_deg) : e.p0;
  return e;
}

double entry_feed(const CutParams& cut) { return cut.feed_entry > 0 ? cut.feed_entry : cut.feed_plunge; }

/// A helix or ramp starts ramp_clearance_mm above the material top: from approach height the tool
/// feeds straight down to it (at 3° every 0.1 mm of descent is 1.9 mm of ramp at the entry feed;
/// until 2026-11-25 the ramp began at approach height, 1 mm up, 0.09 min an entry).
double ramp_start(Builder& b, double top) {
  const double z = std::min(b.pos[2], top + b.gp.ramp_clearance_mm);
  if (b.pos[2] > z + kZEps) b.line(b.pos[0], b.pos[1], z, b.gp.cut.feed_plunge);
  return z;
}

/// A ramp along the chain's first (straight) segment: the tool stays on the chain's own footprint,
/// so it sweeps nothing the chain does not. False (nothing added) where it does not fit.
bool ramp_entry(Builder& b, const LevelPlan& L, const Chain& ch, const EntryPlan& e) {
  if (!e.rampable) return false;
  const GcodeParams& gp = b.gp;
  const Vec2& p0 = e.p0;
  const Vec2 p1 = ch.pts[1].p();
  const double seg = (p1 - p0).norm();
  const double Lr = std::min(seg, 2 * gp.cut.tool.diameter);
  const double z0 = ramp_start(b, L.top_z);
  const double slope = std::tan(gp.entry_angle_deg * kGcodePi / 180);
  int legs = std::max(2, static_cast<int>(std::ceil((z0 - L.z) / (Lr * slope) - 1e-9)));
  if (legs % 2 == 1) ++legs;  // end back at p0
  // Legs shortened to descend at exactly the entry angle: the ramp is (z0 − z) / tan(angle)
  // long, whatever the rounding to an even number of legs.
  const Vec2 q = p0 + (p1 - p0) * ((z0 - L.z) / (legs * slope) / seg);
  for (int k = 1; k <= legs; ++k) {
    const Vec2& t = (k % 2 == 1) ? q : p0;
    b.line(t.x(), t.y(), z0 - (z0 - L.z) * k / legs, entry_feed(gp.cut));
  }
  b.moves[b.moves.size() - static_cast<std::size_t>(legs)].comment = "ramp entry";
  return true;
}

/// The helix, its flat turn included. False (nothing added) where none fits.
bool helix_entry(Builder& b, const LevelPlan& L, const EntryPlan& e) {
  if (!e.hx) return false;
  const CutParams& cut = b.gp.cut;
  const double feed = entry_feed(cut);
  const std::size_t at = b.moves.size();
  helix(b, e.start, e.p0, e.hx->first, e.hx->second, ramp_start(b, L.top_z), L.z, feed, b.gp.entry_angle_deg,
        std::max(feed, cut.feed_slot > 0 ? cut.feed_slot : cut.feed_half), cut.feed_air);
  if (at < b.moves.size()) b.moves[at].comment = "helix entry, radius " + fmt(e.hx->second, kCommentDecimals);
  return true;
}

/// The descent into the chain from above its start. Entry "ramp" tries a ramp first and falls back
/// to a helix; entry "helix" falls back to a ramp where no helix fits (at a wall, where every
/// zigzag pass ends): a plain plunge into uncut material only where neither fits. Returns whether
/// the helix entered it (its flat turn cut the chain's own turn round the bore).
bool enter_chain(Builder& b, const LevelPlan& L, const Chain& ch, const EntryPlan& e) {
  const GcodeParams& gp = b.gp;
  bool entered = false, helixed = false;
  if (gp.entry == Entry::Ramp) {
    entered = ramp_entry(b, L, ch, e);
    if (!entered) entered = helixed = helix_entry(b, L, e);
  } else if (gp.entry == Entry::Helix) {
    entered = helixed = helix_entry(b, L, e);
    if (!entered) entered = ramp_entry(b, L, ch, e);
  }
  if (!entered) {
    b.line(e.p0.x(), e.p0.y(), L.z, gp.cut.feed_plunge);
    if (ch.predrill && gp.entry != Entry::Predrill)
      b.moves.back().comment = "WARNING: no room for a " + std::string(to_string(gp.entry)) + " entry: plain plunge";
  }
  return helixed;
}

/// The chain's moves at depth z from vertex k0 on, at its own feeds (feed_half where it has none).
void cut_chain(Builder& b, const Chain& ch, double z, std::size_t k0) {
  for (std::size_t k = k0; k + 1 < ch.pts.size(); ++k) {
    const double f = (k < ch.feed.size() && ch.feed[k] > 0) ? ch.feed[k] : b.gp.cut.feed_half;
    const Vertex& a = ch.pts[k];
    const Vertex& e = ch.pts[k + 1];
    if (a.bulge == 0.0) {
      b.line(e.x, e.y, z, f);
    } else {
      const Arc arc = arc_of(Segment{a.p(), e.p(), a.bulge});
      b.arc(arc.sweep > 0, arc.center, e.x, e.y, z, f);
    }
  }
}

/// Level li of n: its chains in order, each entered from above its start and cut.
void cut_level(Builder& b, const LevelPlan& L, std::size_t li, std::size_t n) {
  const GcodeParams& gp = b.gp;
  std::optional<Clearance> clear;
  if (gp.entry == Entry::Helix || gp.entry == Entry::Ramp) clear.emplace(L.region, gp.cut.clearance());
  bool first = true;
  for (const Chain& ch : L.path.chains) {
    if (ch.pts.empty()) continue;
    const EntryPlan e = plan_entry(b, L, ch, clear);
    b.go_above(e.start, L.top_z);
    if (first) {
      b.moves.back().comment =
          "level " + std::to_string(li + 1) + " of " + std::to_string(n) + ": Z " + fmt(L.z, kCommentDecimals);
      first = false;
    }
    const bool helixed = enter_chain(b, L, ch, e);
    // After a helix, from the end of the chain's own turn round its bore (Chain::entry_turn).
    cut_chain(b, ch, L.z, helixed ? std::min(ch.entry_turn, ch.pts.size() - 1) : 0);
  }
}

std::vector<Step> build_steps(const std::vector<LevelPlan>& levels, const GcodeParams& gp) {
  check_gcode_params(gp);
  Builder b{gp, {}, {}, false};
  b.rapid(std::nullopt, std::nullopt, gp.cut.safe_z);
  check_levels(levels);
  if (gp.entry == Entry::Predrill) predrill_holes(b, levels);  // 1. pre-drilling
  for (std::size_t li = 0; li < levels.size(); ++li)           // 2. levels top-down, chains in order
    cut_level(b, levels[li], li, levels.size());
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
  h.push_back("tool diameter " + fmt(c.tool.diameter, d) + " stepover " + fmt(c.stepover, d) + " stock to leave " +
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
      items.emplace_back(gcode::Comment{"PRE-DRILL: load a drill of diameter " + fmt(c.tool.diameter, d) + " mm"});
      items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, c.spindle_rpm});
      in_drill = true;
    }
    if (!m.drill && in_drill) {
      items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, c.spindle_rpm});
      items.emplace_back(
          gcode::Comment{"change to the end mill of diameter " + fmt(c.tool.diameter, d) + " mm, then resume"});
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
