// Program → text (see writer.hpp for the layout and the dialect differences).
#include "millnet/gcode/writer.hpp"

#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/cycles.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace millnet::gcode {

std::string format_number(double v, int decimals) {
  // std::to_chars with a precision writes what printf("%.*f") writes (the exact value rounded to
  // `decimals`), without the locale and format parsing: a finishing program has ~10⁶ numbers.
  std::array<char, 400> buf{};  // |v| < 1.8e308: ≤ 309 digits before the point
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::fixed, decimals);
  std::string s(buf.data(), r.ec == std::errc{} ? r.ptr : buf.data());
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

Dialect linuxcnc(int decimals) {
  Dialect d;
  d.decimals = decimals;
  return d;
}

Dialect grbl(int decimals) {
  Dialect d;
  d.name = "grbl";
  d.decimals = decimals;
  d.tool_change_m6 = false;
  d.optional_stop_m1 = false;
  d.canned_cycles = false;
  d.max_comment_chars = 60;
  return d;
}

Dialect fanuc(int decimals) {
  Dialect d;
  d.name = "fanuc";
  d.decimals = std::min(decimals, 3);
  d.start = "%";
  d.program_number = 1000;
  d.decimal_point = true;
  d.preamble = "G21 G90 G17 G94 G40 G80\nG54";  // no G49: a program without a tool change keeps the active H
  d.end = "G91 G28 Z0.\nG90\nM30\n%";
  d.coolant_on = "M8";
  d.coolant_off = "M9";
  d.tool_length_offset = true;
  d.max_comment_chars = 60;
  return d;
}

const std::vector<DialectEntry>& dialects() {
  static const std::vector<DialectEntry> kDialects = {
      {"linuxcnc", "LinuxCNC (rs274ngc): T<n> M6 tool changes, M1 optional stops", &linuxcnc},
      {"grbl", "GRBL 1.1 (hobby routers): no M6 (a comment and M0 pause), lines within its 80-character buffer", &grbl},
      {"fanuc", "Fanuc-style (Fanuc, Haas, most industrial controls): % O1000, G54, T M6 G43 H, M8/M9, X10. decimals",
       &fanuc},
  };
  return kDialects;
}

std::vector<std::string> dialect_names() {
  std::vector<std::string> names;
  for (const DialectEntry& d : dialects()) names.emplace_back(d.name);
  return names;
}

Dialect in_inches(Dialect d) {
  if (d.inch) return d;
  d.inch = true;
  d.decimals = std::min(d.decimals + 1, 8);
  d.feed_decimals = std::min(d.feed_decimals + 1, 8);
  const auto g21 = d.preamble.find("G21");
  if (g21 != std::string::npos) d.preamble.replace(g21, 3, "G20");
  return d;
}

std::array<double, 4> StockBlock::sides(double width, double depth) const {
  if (size_mm) {
    const auto [sx, sy] = *size_mm;
    if (sx < width - 1e-9 || sy < depth - 1e-9)
      throw Error("/rough/stock_size_mm: a block of " + format_double(sx) + " × " + format_double(sy) +
                  " mm is smaller than the part's footprint " + format_double(width) + " × " + format_double(depth) +
                  " mm");
    const double mx = std::max(0.0, 0.5 * (sx - width)), my = std::max(0.0, 0.5 * (sy - depth));
    return {mx, mx, my, my};
  }
  if (offsets_mm) return *offsets_mm;
  return {margin_mm, margin_mm, margin_mm, margin_mm};
}

Dialect placed(Dialect d, double x0, double y0, double x1, double y1) {
  const std::array<double, 4> m = d.stock.sides(x1 - x0, y1 - y0);
  switch (d.origin_at) {
    case WorkOrigin::PartCorner: d.origin = {x0, y0}; break;
    case WorkOrigin::StockCorner: d.origin = {x0 - m[0], y0 - m[2]}; break;
    case WorkOrigin::StockCentre: d.origin = {0.5 * (x0 - m[0] + x1 + m[1]), 0.5 * (y0 - m[2] + y1 + m[3])}; break;
  }
  d.origin_placed = true;
  return d;
}

std::string to_string(WorkOrigin w) {
  switch (w) {
    case WorkOrigin::PartCorner: return "part footprint's lower-left corner";
    case WorkOrigin::StockCorner: return "stock's lower-left corner";
    case WorkOrigin::StockCentre: return "stock's centre";
  }
  return "?";
}

void shift(Program& program, double dx, double dy) {
  if (dx == 0 && dy == 0) return;
  for (Item& item : program.items)  // O(items)
    if (auto* m = std::get_if<Move>(&item)) {
      m->to[0] += dx, m->to[1] += dy;
      m->center[0] += dx, m->center[1] += dy;
    }
}

Dialect dialect_named(std::string_view name, int decimals) {
  for (const DialectEntry& d : dialects())
    if (d.name == name) return d.make(decimals);
  std::string accepted;
  for (const DialectEntry& d : dialects()) accepted += (accepted.empty() ? "\"" : ", \"") + std::string(d.name) + "\"";
  throw Error("gcode: dialect must be one of " + accepted + ", got \"" + std::string(name.substr(0, 40)) + "\"");
}

namespace {

/// A comment's text as one line the reader reads back: parentheses become brackets (a nested
/// comment is an error in rs274ngc) and control bytes '?' (a newline in a file stem broke the
/// program's title comment in two; issue 42 §10, tests/gcode/test_writer.cpp).
std::string comment_text(std::string_view text) {
  std::string t(text);
  for (char& c : t) {
    if (c == '(')
      c = '[';
    else if (c == ')')
      c = ']';
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      c = '?';
  }
  return t;
}

/// Writes items in order, remembering what the controller already knows (position per axis, feed).
class Writer {
public:
  explicit Writer(const Dialect& d) : d_(d), unit_(d.inch ? 1 / 25.4 : 1.0) {}

  void comment(std::string_view text) {
    std::string t = comment_text(text);
    if (d_.max_comment_chars > 0 && t.size() > d_.max_comment_chars) t.resize(d_.max_comment_chars);
    os_ << "(" << t << ")\n";
  }
  void line(std::string_view s) { os_ << s << "\n"; }

  void operator()(const Move& m) {
    for (double v : m.to) finite(v, "coordinate");
    for (double v : m.center) finite(v, "arc centre");
    finite(m.feed, "feed");
    const bool arc = m.motion == Motion::ArcCW || m.motion == Motion::ArcCCW;
    os_ << "G" << static_cast<int>(m.motion);
    const bool compensate = pending_length_offset_ > 0;
    if (compensate) {  // G43 H with the move's Z (the Z written even when it does not change)
      os_ << " G43 H" << pending_length_offset_;
      pending_length_offset_ = 0;
    }
    static constexpr std::array<char, 3> kAxis{'X', 'Y', 'Z'};
    std::array<std::string, 3> stated;  // the text of each axis the block states
    for (std::size_t a = 0; a < 3; ++a) {
      if ((m.axes & (1U << a)) == 0 && !(arc && a < 2)) continue;
      stated[a] = num(out(a, m.to[a]));
      if (!known_[a] || stated[a] != pos_text(a) || (arc && a < 2) || (compensate && a == 2)) {
        os_ << " " << kAxis[a] << stated[a];
        known_[a] = true;
      }
    }
    if (arc) os_ << " I" << num((m.center[0] - pos_[0]) * unit_) << " J" << num((m.center[1] - pos_[1]) * unit_);
    if (m.motion != Motion::Rapid && m.feed != last_feed_) {
      os_ << " F" << point(format_number(m.feed * unit_, d_.feed_decimals));
      last_feed_ = m.feed;
    }
    os_ << "\n";
    // What the controller now knows: the axes the block states (an unstated axis keeps its value,
    // whatever the move's `to` says of it: a program composed of others' items, such as a job's
    // operations, may carry another program's idea of it).
    for (std::size_t a = 0; a < 3; ++a)
      if ((m.axes & (1U << a)) != 0 || (arc && a < 2)) {
        pos_[a] = m.to[a];
        pos_text_[a] = std::move(stated[a]);
        pos_text_known_[a] = true;
      }
  }
  void operator()(const Spindle& s) {
    finite(s.rpm, "spindle speed");
    if (s.dir == SpindleDir::Off && coolant_ && !d_.coolant_off.empty()) line(d_.coolant_off);
    switch (s.dir) {
      case SpindleDir::Off: line("M5"); break;
      case SpindleDir::CW: line("M3 S" + format_number(s.rpm, 0)); break;
      case SpindleDir::CCW: line("M4 S" + format_number(s.rpm, 0)); break;
    }
    if (s.dir != SpindleDir::Off && !coolant_ && !d_.coolant_on.empty()) line(d_.coolant_on);
    coolant_ = s.dir != SpindleDir::Off && !d_.coolant_on.empty();
  }
  void operator()(const ToolChange& t) {
    if (d_.tool_change_m6) {
      os_ << "T" << t.number << " M6";
      if (!t.description.empty()) {
        os_ << " (" << comment_text(t.description) << ")";
      }
      os_ << "\n";
      if (d_.tool_length_offset) pending_length_offset_ = t.length_offset > 0 ? t.length_offset : t.number;
    } else {
      comment("tool change: load T" + std::to_string(t.number) +
              (t.description.empty() ? std::string() : " " + t.description) + ", then resume");
      line("M0");
    }
  }
  void operator()(const Pause& p) { line(p.optional && d_.optional_stop_m1 ? "M1" : "M0"); }

  /// The drilling hole that starts at items[i] written as one canned cycle block: the number of
  /// items it stands for, or 0 when those items are not exactly the moves of one hole from here
  /// (drill_cycle_moves; then they are written as moves). O(moves of the hole).
  std::size_t cycle(const std::vector<Item>& items, std::size_t i) {
    const auto* first = std::get_if<Move>(&items[i]);
    if (!d_.canned_cycles || first == nullptr || first->cycle == 0 || pending_length_offset_ > 0 || !known_[0] ||
        !known_[1] || !known_[2])
      return 0;
    // The hole's figures: the first feed starts at R (its X Y are the hole's); the bottom is the end
    // of one of the feeds that follow (the longest run of items that is exactly one hole wins).
    std::size_t first_feed = items.size();
    Point3 before_feed = pos_;
    std::size_t end = i;
    for (; end < items.size(); ++end) {  // the run of moves marked with this cycle
      const auto* m = std::get_if<Move>(&items[end]);
      if (m == nullptr || m->cycle != first->cycle) break;
      if (m->motion == Motion::Line && first_feed == items.size()) first_feed = end;
      if (first_feed == items.size()) before_feed = m->to;
    }
    if (first_feed == items.size()) return 0;
    const Move& feed = std::get<Move>(items[first_feed]);
    DrillHole h;
    h.x = feed.to[0], h.y = feed.to[1];
    h.r_z = before_feed[2];
    h.peck_mm = first->cycle == 83 ? h.r_z - feed.to[2] : 0;
    h.feed = feed.feed;
    const double series_z = in_cycle_ ? series_z_ : pos_[2];
    std::vector<Move> want;
    for (std::size_t b = first_feed; b < end; ++b) {  // O(feeds of the run × moves of a hole)
      const Move& bottom = std::get<Move>(items[b]);
      if (bottom.motion != Motion::Line) continue;
      DrillHole c = h;
      c.bottom_z = bottom.to[2];
      std::vector<Move> moves = drill_cycle_moves(pos_, kXYZ, c, series_z);
      if (moves.size() > end - i || moves.size() <= want.size()) continue;
      bool same = true;
      for (std::size_t n = 0; n < moves.size() && same; ++n) {
        const Move& m = std::get<Move>(items[i + n]);
        same = m.motion == moves[n].motion && m.to == moves[n].to && (m.motion != Motion::Line || m.feed == h.feed);
      }
      if (same) want = std::move(moves), h.bottom_z = c.bottom_z;
    }
    if (want.empty()) return 0;
    // The block: the cycle and its figures where they change (all of them on a series' first hole).
    const bool start = !in_cycle_ || cycle_code_ != first->cycle;
    if (start) os_ << (in_cycle_ ? "" : "G98 ") << "G" << static_cast<int>(first->cycle);
    const char* sep = start ? " " : "";
    os_ << sep << "X" << num(out(0, h.x)) << " Y" << num(out(1, h.y));
    if (start || h.bottom_z != cycle_z_) os_ << " Z" << num(out(2, h.bottom_z));
    if (start || h.r_z != cycle_r_) os_ << " R" << num(out(2, h.r_z));
    if (h.peck_mm > 0 && (start || h.peck_mm != cycle_q_)) os_ << " Q" << num(h.peck_mm * unit_);
    if (h.feed != last_feed_) os_ << " F" << point(format_number(h.feed * unit_, d_.feed_decimals));
    os_ << "\n";
    if (!in_cycle_) series_z_ = pos_[2];
    in_cycle_ = true;
    cycle_code_ = first->cycle;
    cycle_z_ = h.bottom_z, cycle_r_ = h.r_z, cycle_q_ = h.peck_mm;
    last_feed_ = h.feed;
    pos_ = want.back().to;
    pos_text_known_ = {false, false, false};
    return want.size();
  }

  /// Ends a series of canned cycles (G80) before anything but a comment is written.
  void end_cycles(const Item& next) {
    if (in_cycle_ && !std::holds_alternative<Comment>(next)) end_cycles();
  }
  void end_cycles() {
    if (in_cycle_) line("G80");
    in_cycle_ = false;
  }
  void operator()(const Comment& c) { comment(c.text); }

  std::string text() const { return os_.str(); }

private:
  std::string num(double v) const { return point(format_number(v, d_.decimals)); }
  /// num() of axis a's position as the controller knows it, formatted once per position.
  const std::string& pos_text(std::size_t a) {
    if (!pos_text_known_[a]) {
      pos_text_[a] = num(out(a, pos_[a]));
      pos_text_known_[a] = true;
    }
    return pos_text_[a];
  }
  /// Axis a's value as written: in the work frame (X Y less the origin), in the program's units.
  double out(std::size_t a, double v) const { return (a < 2 ? v - d_.origin[a] : v) * unit_; }
  /// "10" → "10." where the dialect wants a decimal point on every number.
  std::string point(std::string s) const {
    if (d_.decimal_point && s.find('.') == std::string::npos) s += '.';
    return s;
  }
  static void finite(double v, const char* what) {
    if (!std::isfinite(v)) throw Error(std::string("gcode: non-finite ") + what + " in the program");
  }

  const Dialect& d_;
  double unit_;  ///< program units per mm
  std::ostringstream os_;
  Point3 pos_{0, 0, 0};
  std::array<std::string, 3> pos_text_;  ///< num() of pos_, where pos_text_known_
  std::array<bool, 3> pos_text_known_{false, false, false};
  std::array<bool, 3> known_{false, false, false};
  double last_feed_ = -1;
  int pending_length_offset_ = 0;                   ///< the tool whose G43 H the next move carries (0: none)
  bool in_cycle_ = false;                           ///< a series of canned cycles is in effect (G80 ends it)
  std::uint8_t cycle_code_ = 0;                     ///< its G code (81, 83)
  double series_z_ = 0;                             ///< Z before the series: where G98 retracts
  double cycle_z_ = 0, cycle_r_ = 0, cycle_q_ = 0;  ///< its modal Z, R, Q, mm
  bool coolant_ = false;                            ///< coolant on (with the spindle)
};

}  // namespace

std::string write(const Program& program, const Dialect& dialect) {
  if (dialect.decimals < 3 || dialect.decimals > 8) throw Error("gcode: decimals must be in [3, 8]");
  if (dialect.feed_decimals < 0 || dialect.feed_decimals > 8) throw Error("gcode: feed decimals must be in [0, 8]");
  Writer w(dialect);
  if (!dialect.start.empty()) w.line(dialect.start);
  if (dialect.program_number > 0) w.line("O" + std::to_string(dialect.program_number));
  for (const std::string& h : program.header) w.comment(h);
  if (dialect.inch) w.comment("units: inch (G20), feeds in/min");
  if (dialect.origin_placed && dialect.origin_at != WorkOrigin::PartCorner)
    w.comment("work origin: X0 Y0 = the " + to_string(dialect.origin_at) + " (the part's lower-left corner at X" +
              format_number(-dialect.origin[0], 3) + " Y" + format_number(-dialect.origin[1], 3) + " mm)");
  w.line(dialect.preamble);
  for (std::size_t i = 0; i < program.items.size();) {  // O(items)
    if (const std::size_t n = w.cycle(program.items, i); n > 0) {
      i += n;
      continue;
    }
    w.end_cycles(program.items[i]);
    std::visit(w, program.items[i]);
    ++i;
  }
  w.end_cycles();
  w.line(dialect.end);
  return w.text();
}

Written written(const Program& program, const Dialect& dialect, std::string_view source_name) {
  Written w;
  w.text = write(program, dialect);
  w.program = read(w.text, source_name);
  shift(w.program, dialect.origin[0], dialect.origin[1]);  // back into millnet's frame
  return w;
}

Written write_program(const std::filesystem::path& path, const Program& program, const Dialect& dialect) {
  Written w = written(program, dialect, path.string());
  write_file_atomic(path, w.text);
  return w;
}

}  // namespace millnet::gcode
