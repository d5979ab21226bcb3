#pragma once
// An independent check of GRBL 1.1's G-code grammar for the tests (issue 36, issue 40): GRBL's own
// parser rules as its sources state them (grbl/protocol.c: line filtering and the 80-byte line
// buffer; grbl/gcode.c: words, modal groups, supported codes, feed and arc checks; grbl/report.h:
// the error numbers), written down here from scratch. It shares no code with millnet's writer or
// reader, so a program that passes it is one GRBL would run without an error line.
//
// Not modelled: settings ($), jogging, probing, tool length offsets, G10/G28/G30/G92 details
// (millnet writes none of them: the check reports them as unsupported here, which is stricter).
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace millnet::testing {

struct GrblError {
  int line = 0;  ///< 1-based
  int code = 0;  ///< GRBL's error number (report.h), 0 for the sender's serial-buffer limit
  std::string what;
};

/// Every error GRBL 1.1 would report for `program`, in line order (empty: GRBL accepts it all).
inline std::vector<GrblError> grbl_errors(const std::string& program) {
  constexpr std::size_t kLineBuffer = 80;     // LINE_BUFFER_SIZE: at most 79 characters kept per line
  constexpr std::size_t kSerialBuffer = 128;  // RX_BUFFER_SIZE: a streamed line must fit, comments too
  constexpr int kMaxTool = 255;               // MAX_TOOL_NUMBER
  std::vector<GrblError> errors;
  bool feed_defined = false;
  int motion = -1;  // modal motion: 0 1 2 3, -1 none yet (GRBL starts in G0)
  bool inch = false, absolute = true;
  double pos[3] = {0, 0, 0};
  std::istringstream in(program);
  std::string raw;
  int ln = 0;
  while (std::getline(in, raw)) {
    ++ln;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    auto fail = [&](int code, const std::string& what) { errors.push_back({ln, code, what + ": " + raw}); };
    if (raw.size() + 1 > kSerialBuffer) fail(0, "longer than the 128-byte serial buffer");
    // protocol.c: drop whitespace, control characters and comments, capitalise.
    std::string line;
    bool paren = false, semi = false, overflow = false;
    for (const char c : raw) {
      if (semi) continue;
      if (paren) {
        if (c == ')') paren = false;
        continue;
      }
      if (static_cast<unsigned char>(c) <= ' ') continue;
      if (c == '/') continue;  // block delete: ignored
      if (c == '(') {
        paren = true;
        continue;
      }
      if (c == ';') {
        semi = true;
        continue;
      }
      if (line.size() >= kLineBuffer - 1) {
        overflow = true;
        continue;
      }
      line += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    if (overflow) {
      fail(11, "more than 79 characters");
      continue;
    }
    if (line.empty()) continue;
    // gcode.c STEP 2: words.
    struct Word {
      char letter;
      double value;
    };
    std::vector<Word> words;
    bool bad = false;
    for (std::size_t i = 0; i < line.size() && !bad;) {
      const char letter = line[i++];
      if (letter < 'A' || letter > 'Z') {
        fail(1, "expected a command letter");
        bad = true;
        break;
      }
      const std::size_t start = i;
      if (i < line.size() && (line[i] == '-' || line[i] == '+')) ++i;
      bool digits = false, point = false;  // read_float: digits with at most one decimal point
      while (i < line.size() && (std::isdigit(static_cast<unsigned char>(line[i])) || (line[i] == '.' && !point))) {
        point = point || line[i] == '.';
        digits = digits || line[i] != '.';
        ++i;
      }
      if (!digits) {
        fail(2, "bad number format");
        bad = true;
        break;
      }
      words.push_back({letter, std::strtod(line.substr(start, i - start).c_str(), nullptr)});
    }
    if (bad) continue;
    int groups = 0, values = 0;  // bit masks of modal groups (G 0–10, M 16–18) and value words seen
    std::optional<int> new_motion;
    bool axis_command = false;
    std::optional<double> xyz[3], ij[2], f, r;
    for (const Word& w : words) {
      const int whole = static_cast<int>(std::trunc(w.value));
      const int mantissa = static_cast<int>(std::lround(100 * (w.value - whole)));
      auto group = [&](int g) {
        if (groups & (1 << g)) fail(21, "two commands of one modal group");
        groups |= 1 << g;
      };
      if (w.letter == 'G') {
        if (mantissa != 0 && !(whole == 91 && mantissa == 10) && !(whole == 43 && mantissa == 10) &&
            !(whole == 61 && mantissa == 0)) {
          fail(whole == 64 ? 20 : 23, "unsupported or non-integer G code");
          continue;
        }
        switch (whole) {
          case 0:
          case 1:
          case 2:
          case 3:
            if (axis_command) fail(24, "axis command conflict");
            axis_command = true;
            new_motion = whole;
            group(1);
            break;
          case 80:
            group(1);
            new_motion = -1;
            break;
          case 4:
          case 53: group(0); break;
          case 17:
          case 18:
          case 19: group(2); break;
          case 90:
          case 91:
            group(mantissa == 0 ? 3 : 4);  // G91.1 is the arc-distance group of its own
            if (mantissa == 0) absolute = whole == 90;
            break;
          case 93:
          case 94: group(5); break;
          case 20:
          case 21:
            group(6);
            inch = whole == 20;
            break;
          case 40: group(7); break;
          case 43:
          case 49: group(8); break;
          case 54:
          case 55:
          case 56:
          case 57:
          case 58:
          case 59: group(9); break;
          case 61: group(10); break;
          default: fail(20, "unsupported G code (e.g. G64, G41, canned cycles)");
        }
      } else if (w.letter == 'M') {
        if (mantissa != 0) {
          fail(23, "non-integer M code");
          continue;
        }
        switch (whole) {
          case 0:
          case 1:
          case 2:
          case 30: group(16); break;  // program flow
          case 3:
          case 4:
          case 5: group(17); break;  // spindle
          case 8:
          case 9: group(18); break;  // coolant
          default: fail(20, "unsupported M code (e.g. M6 tool change)");
        }
      } else {
        static const std::string kValueWords = "FIJKLNPRSTXYZ";
        const auto k = kValueWords.find(w.letter);
        if (k == std::string::npos) {
          fail(20, std::string("unsupported word ") + w.letter + " (e.g. O, H, D, Q, A, B, C)");
          continue;
        }
        if (values & (1 << k)) fail(25, std::string("repeated word ") + w.letter);
        values |= 1 << k;
        if (std::string("FNPTS").find(w.letter) != std::string::npos && w.value < 0) fail(4, "negative value");
        if (w.letter == 'T' && w.value > kMaxTool) fail(38, "tool number above 255");
        const double mm = inch ? w.value * 25.4 : w.value;
        switch (w.letter) {
          case 'X': xyz[0] = mm; break;
          case 'Y': xyz[1] = mm; break;
          case 'Z': xyz[2] = mm; break;
          case 'I': ij[0] = mm; break;
          case 'J': ij[1] = mm; break;
          case 'F': f = w.value; break;
          case 'R': r = mm; break;
          default: break;
        }
      }
    }
    // STEP 3: what the block does.
    if (f) feed_defined = *f > 0;
    if (new_motion) motion = *new_motion;
    const bool axis_words = xyz[0] || xyz[1] || xyz[2];
    bool used_ij = false, used_r = false;
    if (axis_words && motion < 0) fail(31, "axis words with no motion mode");
    if ((axis_words || new_motion) && motion >= 1 && !feed_defined) fail(22, "feed rate undefined");
    double target[3];
    for (int a = 0; a < 3; ++a) target[a] = xyz[a] ? (absolute ? *xyz[a] : pos[a] + *xyz[a]) : pos[a];
    if ((motion == 2 || motion == 3) && (axis_words || (new_motion && (*new_motion == 2 || *new_motion == 3)))) {
      if (!axis_words)
        fail(26, "arc without axis words");
      else if (!xyz[0] && !xyz[1])
        fail(32, "arc without an axis word in its plane");
      if (r) {
        used_r = true;
      } else if (!ij[0] && !ij[1]) {
        fail(35, "arc without offsets in its plane");
      } else {
        used_ij = true;
        const double cx = pos[0] + ij[0].value_or(0), cy = pos[1] + ij[1].value_or(0);
        const double r0 = std::hypot(pos[0] - cx, pos[1] - cy), r1 = std::hypot(target[0] - cx, target[1] - cy);
        const double dr = std::abs(r1 - r0);
        if (dr > 0.005 && (dr > 0.5 || dr > 0.001 * r0)) fail(33, "arc end not on its circle");
      }
    }
    if ((ij[0] || ij[1]) && !used_ij) fail(36, "unused I/J words");
    if (r && !used_r) fail(36, "unused R word");
    if (values & (1 << 4)) fail(36, "L word unused");  // L: only with G10, which millnet never writes
    if (values & (1 << 6)) fail(36, "P word unused");  // P: only with G4/G10/M-codes it never writes
    if (axis_words && motion >= 0)
      for (int a = 0; a < 3; ++a) pos[a] = target[a];
  }
  return errors;
}

/// The errors as text, one per line ("line 12: error 20: unsupported M code …"), "" when none.
inline std::string grbl_report(const std::vector<GrblError>& errors, std::size_t max_lines = 5) {
  std::string s;
  for (std::size_t i = 0; i < errors.size() && i < max_lines; ++i)
    s += "line " + std::to_string(errors[i].line) + ": error " + std::to_string(errors[i].code) + ": " +
         errors[i].what + "\n";
  if (errors.size() > max_lines) s += "… " + std::to_string(errors.size() - max_lines) + " more\n";
  return s;
}

}  // namespace millnet::testing
