// G-code text → Program (see reader.hpp for the accepted subset).
#include "millnet/gcode/reader.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/cycles.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace millnet::gcode {

namespace {

constexpr double kMmPerInch = 25.4;
/// An arc's radius may fall short of half its chord by this much (mm) before the R form is refused.
constexpr double kArcRadiusSlackMm = 1e-4;
// LinuxCNC's rule for an arc by centre (src/emc/rs274ngc/interp_arc.cc, arc_data_ijk, with its
// default tolerances of interp_internal.hh), in the program's unit: a radius below
// kArcZeroRadius is a zero-radius arc; the radius to the end may differ from the radius to the
// start by at most kArcSpiralAbs, or by up to 100 × kArcSpiralAbs when that is at most
// kArcSpiralRel of the larger radius.
constexpr double kArcZeroRadiusInch = 0.00005;                            // RADIUS_TOLERANCE_INCH
constexpr double kArcSpiralAbsMm = 2 * 0.01 * 1.41421356237309504880;     // CENTER_ARC_RADIUS_TOLERANCE_MM
constexpr double kArcSpiralAbsInch = 2 * 0.001 * 1.41421356237309504880;  // CENTER_ARC_RADIUS_TOLERANCE_INCH
constexpr double kArcSpiralRel = 0.001;                                   // SPIRAL_RELATIVE_TOLERANCE
/// Largest tool number a T word may give (LinuxCNC's tool table holds up to 99999 pockets).
constexpr double kMaxToolNumber = 99999;
/// Most pecks one G83 block may make (its depth / Q), and a whole program's G83 blocks together: a
/// bound on the moves short lines may add (3 per peck; 200,000 pecks ≈ 50 MB of moves).
constexpr double kMaxPecks = 10000;
constexpr double kMaxProgramPecks = 200000;
/// Characters of a bad word or comment quoted in a message.
constexpr std::size_t kQuoteChars = 40;

/// Bytes of the input made safe for a one-line message: control bytes and bytes ≥ 0x7F as \xNN,
/// at most kQuoteChars characters, then "…" and the length (a 2,000-digit word, a NUL byte).
std::string quote(std::string_view s) {
  std::string out;
  std::size_t shown = 0;
  for (const char ch : s) {
    if (shown == kQuoteChars) return out + "… (" + std::to_string(s.size()) + " characters)";
    const auto u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      out += buf;
    } else {
      out += ch;
    }
    ++shown;
  }
  return out;
}

/// A number for a message: 6 significant digits, or `digits` (positions: 10, "100000.001").
std::string fmt(double v, int digits = 6) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// The modal groups of RS-274 (LinuxCNC's numbering) a code belongs to; −1 for none tracked.
int g_group(double code) {
  if (!(std::abs(code - std::round(code)) < 1e-9 && std::abs(code) < 1e6)) return -1;  // not a code of ours
  const long c = std::lround(code);
  if (c == 28) return 0;                                              // non-modal (return home)
  if ((c >= 0 && c <= 3) || c == 80 || c == 81 || c == 83) return 1;  // motion (canned cycles too)
  if (c == 17) return 2;                                              // plane
  if (c == 90 || c == 91) return 3;                                   // distance mode
  if (c == 94) return 5;                                              // feed rate mode
  if (c == 20 || c == 21) return 6;                                   // units
  if (c == 40) return 7;                                              // cutter radius compensation
  if (c == 43 || c == 49) return 8;                                   // tool length offset
  if (c == 54) return 12;                                             // coordinate system
  if (c == 98 || c == 99) return 10;                                  // canned cycle return mode
  return -1;
}
int m_group(int code) {
  if (code == 0 || code == 1 || code == 2 || code == 30) return 4;  // stopping
  if (code == 6) return 6;                                          // tool change
  if (code == 3 || code == 4 || code == 5) return 7;                // spindle
  if (code == 8 || code == 9) return 8;                             // coolant
  return -1;
}
const char* group_name(char letter, int group) {
  if (letter == 'G')
    return group == 0    ? "non-modal"
           : group == 1  ? "motion"
           : group == 2  ? "plane"
           : group == 3  ? "distance mode"
           : group == 5  ? "feed rate mode"
           : group == 6  ? "units"
           : group == 7  ? "cutter compensation"
           : group == 8  ? "tool length offset"
           : group == 10 ? "canned cycle return mode"
                         : "coordinate system";
  return group == 4 ? "stopping" : group == 6 ? "tool change" : group == 7 ? "spindle" : "coolant";
}

struct Word {
  char letter = 0;
  double value = 0;
  std::string_view number;  ///< as written (a view into the line being read)
  /// The word for messages: its letter upper-cased and its number as written.
  [[nodiscard]] std::string text() const { return std::string(1, letter) + std::string(number); }
};

/// One line split into words and comment texts.
struct Line {
  std::vector<Word> words;
  std::vector<std::string> comments;
};

char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

class Reader {
public:
  explicit Reader(std::string_view source) : source_(source) {}

  Program run(std::string_view text) {
    std::size_t start = 0;
    while (start <= text.size()) {  // O(characters)
      std::size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      ++line_no_;
      if (!line(text.substr(start, end - start))) break;
      if (end == text.size()) break;
      start = end + 1;
    }
    return std::move(prog_);
  }

private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(std::string(source_) + ":" + std::to_string(line_no_) + ": " + what);
  }

  Line split(std::string_view s) const {
    Line out;
    std::size_t i = 0;
    while (i < s.size()) {
      const char c = s[i];
      if (is_space(c)) {
        ++i;
        continue;
      }
      if (c == '(') {
        std::size_t close = i + 1;
        for (; close < s.size() && s[close] != ')'; ++close)
          if (s[close] == '(')  // LinuxCNC: "Nested comment found"
            fail("nested comment: a '(' at column " + std::to_string(close + 1) +
                 " inside the comment opened at column " + std::to_string(i + 1) + " (RS-274 comments do not nest)");
        if (close == s.size()) fail("comment not closed: " + quote(s.substr(i)));
        out.comments.emplace_back(s.substr(i + 1, close - i - 1));
        i = close + 1;
        continue;
      }
      if (c == ';') {
        std::size_t b = i + 1;
        while (b < s.size() && is_space(s[b])) ++b;
        std::size_t e = s.size();
        while (e > b && is_space(s[e - 1])) --e;
        out.comments.emplace_back(s.substr(b, e - b));
        break;
      }
      const char L = upper(c);
      if (L < 'A' || L > 'Z') fail("unsupported character '" + quote(std::string_view(&c, 1)) + "'");
      std::size_t j = i + 1;
      while (j < s.size() && is_space(s[j])) ++j;
      std::size_t k = j;
      if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
      while (k < s.size() && ((s[k] >= '0' && s[k] <= '9') || s[k] == '.')) ++k;
      Word w;
      w.letter = L;
      w.number = s.substr(j, k - j);
      std::string_view digits = w.number;  // from_chars takes no '+'
      if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
      const char* first = digits.data();
      const char* last = digits.data() + digits.size();
      const auto [ptr, ec] = std::from_chars(first, last, w.value);
      if (!digits.empty() && (ec == std::errc::result_out_of_range || (ec == std::errc() && !std::isfinite(w.value))))
        fail("word " + quote(w.text()) + ": the number does not fit a double");
      if (digits.empty() || ec != std::errc() || ptr != last || !std::isfinite(w.value))
        fail("word " + quote(w.text()) + " has no valid number" +
             (k == j && k < s.size() ? " (followed by '" + quote(s.substr(k, 1)) + "')" : ""));
      out.words.push_back(std::move(w));
      i = k;
    }
    return out;
  }

  static bool is(double v, double code) { return std::abs(v - code) < 1e-9; }

  void add(Item item) {
    prog_.items.push_back(std::move(item));
    prog_.source_line.push_back(line_no_);
  }

  /// The words of one line, sorted by what they do (one per kind; M-codes in order).
  struct Words {
    std::optional<Motion> motion;
    std::array<std::optional<double>, 3> axis{};
    std::optional<double> i_word, j_word, r_word, f_word, s_word, t_word, h_word, q_word;
    int cycle = 0;                       ///< G81 / G83 on the line
    std::optional<bool> retract_to_old;  ///< G98 (true) / G99 (false)
    bool cancel_motion = false;          ///< G80
    bool home = false;                   ///< G28
    bool length_offset = false;          ///< G43 (with H)
    std::vector<int> m_codes;
    [[nodiscard]] bool has_m(int code) const {
      for (int m : m_codes)
        if (m == code) return true;
      return false;
    }
  };

  /// Handles one line; false once the program has ended (M2 / M30).
  bool line(std::string_view s) {
    const std::size_t b = s.find_first_not_of(" \t\r");
    if (b != std::string_view::npos && s[b] == '%' && s.find_first_not_of(" \t\r", b + 1) == std::string_view::npos)
      return true;  // a programme delimiter line
    Line ln = split(s);
    if (ln.words.size() == 1 && ln.words[0].letter == 'O' && !seen_words_) ln.words.clear();  // O1000: a program number
    if (ln.words.empty()) {
      for (std::string& c : ln.comments) {
        if (!seen_words_) {
          prog_.header.push_back(std::move(c));
        } else if (std::optional<ToolChange> tc = manual_tool_change(c)) {
          add(std::move(*tc));  // a dialect without M6 (GRBL): the change is this comment and an M0
          manual_change_pause_ = true;
        } else {
          add(Comment{std::move(c)});
        }
      }
      return true;
    }
    seen_words_ = true;
    const bool swallow_pause = std::exchange(manual_change_pause_, false) && ln.words.size() == 1 &&
                               ln.words[0].letter == 'M' && is(ln.words[0].value, 0);
    const Words w = sort_words(ln);
    apply_modal(w);
    add_comments_and_tool_change(w, ln);
    const int spindle_m = w.has_m(3) ? 3 : w.has_m(4) ? 4 : w.has_m(5) ? 5 : 0;
    if (spindle_m != 0) {
      dir_ = spindle_m == 3 ? SpindleDir::CW : spindle_m == 4 ? SpindleDir::CCW : SpindleDir::Off;
      add(Spindle{dir_, rpm_});
    } else if (w.s_word && dir_ != SpindleDir::Off) {
      add(Spindle{dir_, rpm_});
    }
    const bool any_axis = w.axis[0] || w.axis[1] || w.axis[2];
    if (w.home)
      home(w);
    else if (cycle_ != 0 && (any_axis || w.r_word || w.q_word))
      drill_cycle(w);
    else if (any_axis || w.i_word || w.j_word || w.r_word)
      move(w.axis, w.i_word, w.j_word, w.r_word);
    if ((w.has_m(0) && !swallow_pause) || w.has_m(1)) add(Pause{!w.has_m(0)});
    return !(w.has_m(2) || w.has_m(30));
  }

  /// The comment the writer makes of a tool change where the dialect has no M6 (writer.cpp: "tool
  /// change: load T<n>[ <description>], then resume", then M0), read back as that tool change; the
  /// M0 right after it belongs to it. Anything else: nothing.
  static std::optional<ToolChange> manual_tool_change(const std::string& c) {
    static constexpr std::string_view kPrefix = "tool change: load T";
    if (c.rfind(kPrefix, 0) != 0) return std::nullopt;
    std::size_t k = kPrefix.size();
    int n = 0;
    const std::size_t digits = k;
    while (k < c.size() && k - digits < 5 && std::isdigit(static_cast<unsigned char>(c[k])) != 0)
      n = n * 10 + (c[k++] - '0');
    if (k == digits || (k < c.size() && c[k] != ' ' && c[k] != ',')) return std::nullopt;
    ToolChange tc;
    tc.number = n;
    std::string_view rest(c);
    rest.remove_prefix(k < c.size() && c[k] == ' ' ? k + 1 : k);
    if (const std::size_t e = rest.rfind(", then resume"); e != std::string_view::npos) rest = rest.substr(0, e);
    tc.description = std::string(rest);
    return tc;
  }

  /// The line's words by kind, checked as LinuxCNC checks them: one word per letter, one code per
  /// modal group, only the codes millnet reads. G20/G21 and G90/G91 take effect here.
  Words sort_words(const Line& ln) {
    Words out;
    auto once = [&](std::optional<double>& slot, const Word& w) {
      if (slot) fail("word " + std::string(1, w.letter) + " repeated on the line");
      slot = w.value;
    };
    // One code per modal group and line (LinuxCNC: "Two G-codes used from same modal group").
    std::array<const Word*, 16> g_seen{}, m_seen{};
    auto one_per_group = [&](const Word& w, int group, std::array<const Word*, 16>& seen) {
      if (group < 0) return;
      const auto g = static_cast<std::size_t>(group);
      if (seen[g])
        fail("two " + std::string(1, w.letter) + "-codes of one modal group on the line: " + quote(seen[g]->text()) +
             " and " + quote(w.text()) + " (" + group_name(w.letter, group) + ")");
      seen[g] = &w;
    };
    for (const Word& w : ln.words) {
      if (w.letter == 'G') one_per_group(w, g_group(w.value), g_seen);
      if (w.letter == 'M' && std::abs(w.value - std::round(w.value)) < 1e-9 && std::abs(w.value) < 1e6)
        one_per_group(w, m_group(static_cast<int>(std::lround(w.value))), m_seen);
      switch (w.letter) {
        case 'G':
          if (is(w.value, 0))
            out.motion = Motion::Rapid;
          else if (is(w.value, 1))
            out.motion = Motion::Line;
          else if (is(w.value, 2))
            out.motion = Motion::ArcCW;
          else if (is(w.value, 3))
            out.motion = Motion::ArcCCW;
          else if (is(w.value, 17) || is(w.value, 94) || is(w.value, 40) || is(w.value, 49) || is(w.value, 54)) {
          } else if (is(w.value, 80))
            out.cancel_motion = true;
          else if (is(w.value, 81) || is(w.value, 83))
            out.cycle = static_cast<int>(std::lround(w.value));
          else if (is(w.value, 98) || is(w.value, 99))
            out.retract_to_old = is(w.value, 98);
          else if (is(w.value, 28))
            out.home = true;
          else if (is(w.value, 43))
            out.length_offset = true;
          else if (is(w.value, 20))
            scale_ = kMmPerInch;
          else if (is(w.value, 21))
            scale_ = 1;
          else if (is(w.value, 90))
            incremental_ = false;
          else if (is(w.value, 91))
            incremental_ = true;
          else
            fail("unsupported word " + quote(w.text()));
          break;
        case 'M':
          if (is(w.value, 0) || is(w.value, 1) || is(w.value, 2) || is(w.value, 3) || is(w.value, 4) ||
              is(w.value, 5) || is(w.value, 6) || is(w.value, 8) || is(w.value, 9) || is(w.value, 30))
            out.m_codes.push_back(static_cast<int>(std::lround(w.value)));
          else
            fail("unsupported word " + quote(w.text()));
          break;
        case 'X': once(out.axis[0], w); break;
        case 'Y': once(out.axis[1], w); break;
        case 'Z': once(out.axis[2], w); break;
        case 'I': once(out.i_word, w); break;
        case 'J': once(out.j_word, w); break;
        case 'R': once(out.r_word, w); break;
        case 'F': once(out.f_word, w); break;
        case 'S': once(out.s_word, w); break;
        case 'T': once(out.t_word, w); break;
        case 'H': once(out.h_word, w); break;
        case 'Q': once(out.q_word, w); break;
        case 'N': break;
        case 'O':  // a Fanuc program number is read only alone on its line, before any other word (line())
          fail("O-word " + quote(w.text()) +
               ": only a program number alone on the first line with words is read (no subroutines)");
        default: fail("unsupported word " + quote(w.text()));
      }
    }
    return out;
  }

  /// Motion mode, feed, spindle speed and tool number of the line, checked.
  void apply_modal(const Words& w) {
    const int cycle_before = cycle_;
    if (w.motion) motion_ = w.motion, cycle_ = 0;
    if (w.cancel_motion) motion_.reset(), cycle_ = 0;
    if (w.cycle != 0) motion_.reset(), cycle_ = w.cycle;
    if (cycle_ != 0 && cycle_before == 0) {  // a series of cycles starts: G98 returns to this Z
      series_z_ = pos_[2];
      series_z_known_ = (known_ & kZ) != 0;
      series_first_ = true;
    }
    if (w.retract_to_old) retract_to_old_ = *w.retract_to_old;
    if (w.q_word && cycle_ == 0) fail("Q word outside a G83 cycle");
    if (w.h_word && !w.length_offset) fail("H word without G43");
    if (w.length_offset) {
      if (!w.h_word) fail("G43 without an H word (the tool length offset)");
      if (!(*w.h_word >= 0 && *w.h_word <= kMaxToolNumber && *w.h_word == std::round(*w.h_word)))
        fail("tool length offset H" + fmt(*w.h_word, 10) + " is not an offset number (0 to " + fmt(kMaxToolNumber) +
             ")");
    }
    if (w.f_word) {
      if (*w.f_word < 0) fail("negative feed F" + std::to_string(*w.f_word));
      feed_ = *w.f_word * scale_;
    }
    if (w.s_word) {
      if (*w.s_word < 0) fail("negative spindle speed");
      rpm_ = *w.s_word;
    }
    if (w.t_word) {
      if (!(*w.t_word >= 0 && *w.t_word <= kMaxToolNumber))
        fail("tool number T" + fmt(*w.t_word, 10) + " out of range (0 to " + fmt(kMaxToolNumber) + ")");
      tool_ = static_cast<int>(std::lround(*w.t_word));
    }
  }

  /// The line's comments; with M6, the tool change (its first comment is the tool's description).
  void add_comments_and_tool_change(const Words& w, const Line& ln) {
    std::size_t comment_used = 0;
    if (w.has_m(6)) {
      if (!tool_) fail("M6 without a tool number (T word)");
      ToolChange tc;
      tc.number = *tool_;
      if (!ln.comments.empty()) tc.description = ln.comments.front(), comment_used = 1;
      for (std::size_t c = comment_used; c < ln.comments.size(); ++c) add(Comment{ln.comments[c]});
      add(std::move(tc));
    } else {
      for (const std::string& c : ln.comments) add(Comment{c});
    }
  }

  /// G28 read as Fanuc posts write it, "G91 G28 Z0.": the named axes go straight to the machine's
  /// home, whose place in the program's frame is unknown — those axes are unknown afterwards (no
  /// move is made of it). An intermediate point (absolute, or a non-zero increment) is refused.
  void home(const Words& w) {
    if (!incremental_) fail("G28 is read only as G91 G28 (straight to the machine's home)");
    if (w.i_word || w.j_word || w.r_word || w.motion) fail("G28 with I, J, R or a motion code");
    for (std::size_t a = 0; a < 3; ++a)
      if (w.axis[a]) {
        if (*w.axis[a] != 0) fail("G28 through an intermediate point (only zero increments are read)");
        known_ &= static_cast<std::uint8_t>(~(1U << a));
      }
  }

  void move(const std::array<std::optional<double>, 3>& axis, std::optional<double> i_word,
            std::optional<double> j_word, std::optional<double> r_word) {
    if (!motion_) fail("axis words with no motion mode (G0 G1 G2 G3) in effect");
    Move m;
    m.motion = *motion_;
    const Point3 from = pos_;
    const std::uint8_t known_before = known_;
    for (std::size_t a = 0; a < 3; ++a) {
      if (axis[a]) {
        const double v = *axis[a] * scale_;
        const double to = incremental_ ? pos_[a] + v : v;
        if (!(std::abs(to) <= kMaxCoordinateMm))
          fail(std::string(1, "XYZ"[a]) + " " + fmt(to, 10) + " mm is beyond the travel bound ±" +
               fmt(kMaxCoordinateMm) + " mm" + (incremental_ ? " (G91: the sum of the incremental moves)" : ""));
        pos_[a] = to;
        known_ |= static_cast<std::uint8_t>(1U << a);
      }
    }
    m.to = pos_;
    m.axes = known_;
    const bool arc = m.motion == Motion::ArcCW || m.motion == Motion::ArcCCW;
    if (!arc && (i_word || j_word || r_word)) fail("I, J or R on a straight move");
    if (m.motion != Motion::Rapid) {
      if (!(feed_ > 0)) fail("feed move with no feed rate (F)");
      m.feed = feed_;
    }
    if (arc) {
      if ((known_before & (kX | kY)) != (kX | kY)) fail("arc from an unknown XY position");
      if (r_word) {
        if (i_word || j_word) fail("arc with both R and I J");
        m.center = radius_centre(from, m.to, *r_word * scale_, m.motion == Motion::ArcCCW);
      } else {
        if (!i_word && !j_word) fail("arc with neither I J nor R");
        m.center = {from[0] + i_word.value_or(0) * scale_, from[1] + j_word.value_or(0) * scale_};
      }
      for (std::size_t a = 0; a < 2; ++a)
        if (!(std::abs(m.center[a]) <= kMaxCoordinateMm))
          fail(std::string("arc centre ") + "XY"[a] + " " + fmt(m.center[a], 10) + " mm is beyond the travel bound ±" +
               fmt(kMaxCoordinateMm) + " mm");
      if (!r_word) check_centre(from, m.to, m.center);
    }
    add(m);
  }

  /// One block of a G81 / G83 cycle, expanded as LinuxCNC expands it (gcode/cycles.hpp). Z, R and Q
  /// are modal within the cycle mode; checked as LinuxCNC checks them (R at or above Z, Q > 0, a
  /// feed), and the pecks bounded (kMaxPecks).
  void drill_cycle(const Words& w) {
    const char* name = cycle_ == 81 ? "G81" : "G83";
    if (incremental_) fail(std::string(name) + " in G91: drilling cycles are read in absolute mode (G90) only");
    if (w.i_word || w.j_word) fail(std::string("I or J on a ") + name + " drilling cycle");
    if (w.axis[2]) cycle_z_ = *w.axis[2] * scale_;
    if (w.r_word) cycle_r_ = *w.r_word * scale_;
    if (w.q_word) cycle_q_ = *w.q_word * scale_;
    if (!cycle_z_) fail(std::string(name) + " without a Z word (the hole's bottom)");
    if (!cycle_r_) fail(std::string(name) + " without an R word (the plane the feed starts from)");
    if (!series_z_known_) fail(std::string(name) + " from an unknown Z (no Z stated before the cycle)");
    DrillHole h;
    for (std::size_t a = 0; a < 2; ++a) {
      if (!w.axis[a] && (known_ & (1U << a)) == 0)
        fail(std::string(name) + " at an unknown " + "XY"[a] + " (none stated before it)");
      (a == 0 ? h.x : h.y) = w.axis[a] ? *w.axis[a] * scale_ : pos_[a];
    }
    h.bottom_z = *cycle_z_, h.r_z = *cycle_r_;
    for (const double v : {h.x, h.y, h.bottom_z, h.r_z})
      if (!(std::abs(v) <= kMaxCoordinateMm))
        fail(std::string(name) + ": " + fmt(v, 10) + " mm is beyond the travel bound ±" + fmt(kMaxCoordinateMm) +
             " mm");
    if (h.r_z < h.bottom_z)
      fail(std::string(name) + ": R " + fmt(h.r_z / scale_) + " is below the hole's bottom Z " +
           fmt(h.bottom_z / scale_) + " (LinuxCNC: R value less than Z value in canned cycle)");
    if (cycle_ == 83) {
      if (!cycle_q_ || !(*cycle_q_ > 0)) fail("G83 without a Q word > 0 (the depth of each peck)");
      if ((h.r_z - h.bottom_z) / *cycle_q_ > kMaxPecks)
        fail("G83: Q " + fmt(*cycle_q_ / scale_) + " over a hole " + fmt((h.r_z - h.bottom_z) / scale_) +
             " deep makes more than " + fmt(kMaxPecks) + " pecks");
      h.peck_mm = *cycle_q_;
      pecks_ += std::ceil((h.r_z - h.bottom_z) / h.peck_mm);
      if (pecks_ > kMaxProgramPecks)
        fail("G83: the program's drilling cycles make more than " + fmt(kMaxProgramPecks) + " pecks");
    }
    if (!(feed_ > 0)) fail(std::string(name) + " with no feed rate (F)");
    h.feed = feed_;
    const double retract = retract_to_old_ ? std::max(series_z_, h.r_z) : h.r_z;
    if (!series_first_ && pos_[2] < h.r_z) {  // LinuxCNC: within a series, below R, one traverse to the hole at R
      Move up;
      up.to = {h.x, h.y, h.r_z};
      up.axes = static_cast<std::uint8_t>(known_ | kXYZ);
      up.cycle = static_cast<std::uint8_t>(cycle_);
      pos_ = up.to, known_ = up.axes;
      add(up);
    }
    series_first_ = false;
    for (Move& m : drill_cycle_moves(pos_, known_, h, retract)) {  // O(pecks)
      pos_ = m.to;
      known_ = m.axes;
      add(m);
    }
  }

  /// LinuxCNC's check of an arc given by its centre (interp_arc.cc, arc_data_ijk), in the
  /// program's unit: neither radius zero, and the end on the circle within its tolerances.
  void check_centre(const Point3& a, const Point3& b, const std::array<double, 2>& c) const {
    const double r1 = std::hypot(a[0] - c[0], a[1] - c[1]) / scale_, r2 = std::hypot(b[0] - c[0], b[1] - c[1]) / scale_;
    const bool inch = scale_ != 1;
    const char* unit = inch ? " in" : " mm";
    const double zero = inch ? kArcZeroRadiusInch : kArcZeroRadiusInch * kMmPerInch;
    if (r1 < zero || r2 < zero)
      fail("zero-radius arc: radius " + fmt(r1) + unit + " at the start, " + fmt(r2) + unit + " at the end (at least " +
           fmt(zero) + unit + ")");
    const double spiral = inch ? kArcSpiralAbsInch : kArcSpiralAbsMm;
    const double err = std::abs(r1 - r2), rel = err / std::max(r1, r2);
    if (err > 100 * spiral || (rel > kArcSpiralRel && err > spiral))
      fail("the arc's end is not on its circle: radius " + fmt(r1) + unit + " at the start, " + fmt(r2) + unit +
           " at the end (LinuxCNC allows a difference of " + fmt(spiral) + unit + ", or of " +
           fmt(100 * kArcSpiralRel) + " % up to " + fmt(100 * spiral) + unit + ")");
  }

  std::array<double, 2> radius_centre(const Point3& a, const Point3& b, double r, bool ccw) const {
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const double d = std::hypot(dx, dy);
    if (d < 1e-12) fail("arc by radius R with the same start and end");
    const double h2 = r * r - d * d / 4;
    if (h2 < -kArcRadiusSlackMm * std::abs(r)) fail("arc radius R too small to reach the end point");
    const double h = std::sqrt(std::max(0.0, h2));
    // The shorter arc has its centre on the left of the chord when counter-clockwise.
    const double side = (ccw ? 1.0 : -1.0) * (r > 0 ? 1.0 : -1.0);
    return {(a[0] + b[0]) / 2 - side * h * dy / d, (a[1] + b[1]) / 2 + side * h * dx / d};
  }

  std::string_view source_;
  std::size_t line_no_ = 0;
  Program prog_;
  bool seen_words_ = false;
  bool manual_change_pause_ = false;  ///< a manual tool change comment was just read: its M0 follows
  double scale_ = 1;                  ///< mm per program unit
  bool incremental_ = false;
  std::optional<Motion> motion_;
  int cycle_ = 0;               ///< the drilling cycle in effect (81, 83) instead of motion_; 0: none
  bool retract_to_old_ = true;  ///< G98 (the default here) / G99
  double series_z_ = 0;         ///< Z when the current series of cycles began (G98 returns there)
  bool series_z_known_ = false;
  bool series_first_ = false;
  double pecks_ =
      0;  ///< pecks of the G83 blocks read so far                          ///< the next cycle block is its series' first
  std::optional<double> cycle_z_, cycle_r_, cycle_q_;  ///< modal Z, R, Q of the cycles, mm
  double feed_ = 0;                                    ///< mm/min
  double rpm_ = 0;
  SpindleDir dir_ = SpindleDir::Off;
  std::optional<int> tool_;
  Point3 pos_{0, 0, 0};
  std::uint8_t known_ = 0;
};

}  // namespace

Program read(std::string_view text, std::string_view source_name) { return Reader(source_name).run(text); }

}  // namespace millnet::gcode
