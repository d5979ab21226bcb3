// LinuxCNC's tool table (tool.tbl): read into tooling::Tool, and written from them.
//
// The grammar, from LinuxCNC's docs (docs/src/gcode/tool-compensation.adoc, "Tool Table Format") and
// its reader (src/emc/tooldata/tooldata_common.cc, tooldata_read_entry): a line is split at its first
// ';' (the rest is the comment, kept up to 39 characters); a line starting with ';' is ignored; the
// words before it are separated by blanks, each a letter (either case) and its number: T tool number
// and P pocket (integers, both required), X Y Z A B C U V W offsets, D diameter, I J lathe angles
// (reals), Q lathe orientation (integer). LinuxCNC skips a line with any other word; this reader
// refuses it, naming the line. Lines are read up to 255 characters (fgets of 256).
#include "common.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>

namespace millnet::tooling::io {
using namespace detail;

namespace {

constexpr std::string_view kWords = "TPDXYZABCUVWIJQ";
constexpr double kMmPerInch = 25.4;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n\v\f");
  if (b == std::string_view::npos) return {};
  return std::string(s.substr(b, s.find_last_not_of(" \t\r\n\v\f") - b + 1));
}

std::vector<std::string> split(std::string_view s, std::string_view seps) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = s.find_first_not_of(seps, i);
    if (b == std::string_view::npos) break;
    const auto e = std::min(s.find_first_of(seps, b), s.size());
    out.emplace_back(s.substr(b, e - b));
    i = e;
  }
  return out;
}

bool has(const std::string& text, std::initializer_list<const char*> words) {
  return std::any_of(words.begin(), words.end(), [&](const char* w) { return text.find(w) != std::string::npos; });
}

/// What a comment says about the tool. "<name>: <rest>" (a name without blanks, as the export
/// writes) names the tool; the rest describes it.
struct CommentFacts {
  std::string name;
  std::optional<ToolType> type;
  std::optional<double> corner_mm;
  std::optional<int> flutes;
  std::optional<ToolMaterial> material;
};

/// A length word of a comment in the table's units unless it says "mm" or "in".
std::optional<double> comment_length(std::string_view s, double table_mm) {
  double k = table_mm;
  if (s.size() > 2 && s.substr(s.size() - 2) == "mm") {
    k = 1;
    s.remove_suffix(2);
  } else if (s.size() > 2 && s.substr(s.size() - 2) == "in") {
    k = kMmPerInch;
    s.remove_suffix(2);
  } else if (s.size() > 1 && s.back() == '"') {
    k = kMmPerInch;
    s.remove_suffix(1);
  }
  const auto v = parse_real(s);
  if (!v) return std::nullopt;
  return to_mm(*v, k);
}

CommentFacts read_comment(const std::string& comment, double table_mm) {
  CommentFacts f;
  std::string body = comment;
  if (const auto colon = comment.find(": ");
      colon != std::string::npos && colon > 0 && comment.find_first_of(" \t") > colon) {
    f.name = comment.substr(0, colon);
    body = comment.substr(colon + 2);
  } else if (!comment.empty() && comment.back() == ':' && comment.find_first_of(" \t") == std::string::npos) {
    f.name = comment.substr(0, comment.size() - 1);
    body.clear();
  }
  const std::string text = lower(body);
  // The type: ball before bull before drill before end mill ("ball end mill" is a ball nose).
  if (has(text, {"ball"}))
    f.type = ToolType::Ball;
  else if (has(text, {"bull", "torus", "toroid", "corner radius", "corner-radius"}))
    f.type = ToolType::Bull;
  else if (has(text, {"drill"}))
    f.type = ToolType::Drill;
  else if (has(text, {"end mill", "endmill", "end-mill", "flat", "slot"}))
    f.type = ToolType::Flat;
  if (has(text, {"hss", "cobalt", "hsco"}))
    f.material = ToolMaterial::HSS;
  else if (has(text, {"carbide", "vhm"}))
    f.material = ToolMaterial::Carbide;
  const std::vector<std::string> words = split(text, " \t,;()[]");
  for (std::size_t i = 0; i < words.size(); ++i) {
    std::string_view w = words[i];
    // Corner radius: "r1", "R0.5", "cr1", "r=1", "radius 1", "radius 0.5mm".
    if (!f.corner_mm && (w == "radius" || w == "cr" || w == "r") && i + 1 < words.size()) {
      f.corner_mm = comment_length(words[i + 1], table_mm);
    } else if (!f.corner_mm && (w.rfind("cr", 0) == 0 || w.rfind("r", 0) == 0)) {
      std::string_view v = w.substr(w[0] == 'c' ? 2 : 1);
      if (!v.empty() && v.front() == '=') v.remove_prefix(1);
      if (!v.empty() && (std::isdigit(static_cast<unsigned char>(v.front())) || v.front() == '.'))
        f.corner_mm = comment_length(v, table_mm);
    }
    // Flutes: "3F", "3fl", "4-flute", "2 flutes".
    if (!f.flutes && !w.empty() && std::isdigit(static_cast<unsigned char>(w.front()))) {
      const auto e = w.find_first_not_of("0123456789");
      const std::string_view digits = w.substr(0, e), rest = e == std::string_view::npos ? "" : w.substr(e);
      const bool flute_word =
          rest == "f" || rest == "fl" || rest == "flt" || rest == "-flute" || rest == "-flutes" || rest == "flute";
      const bool next_is_flute =
          rest.empty() && i + 1 < words.size() && (words[i + 1].rfind("flute", 0) == 0 || words[i + 1] == "fl");
      if (flute_word || next_is_flute) f.flutes = parse_int(digits);
    }
  }
  return f;
}

std::string type_word(ToolType t) { return to_string(t); }

/// A figure for a comment: at most 4 decimals, no trailing zeros.
std::string short_number(double v) { return format_double(std::round(v * 1e4) / 1e4); }

}  // namespace

ToolImport read_linuxcnc_tool_table(std::string_view text, const std::string& source, LengthUnit units) {
  check_size(text.size(), source);
  const double k = units == LengthUnit::Inch ? kMmPerInch : 1.0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte-order mark
  ToolImport out;
  Notes notes;
  IdMaker ids;
  std::map<int, long> line_of;  // tool number → its line
  bool offsets = false, lathe = false, pockets = false;
  long line_no = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() > kLinuxCncMaxLine)
      throw line_error(source, line_no,
                       std::to_string(line.size()) + " characters; LinuxCNC reads a tool-table line up to " +
                           std::to_string(kLinuxCncMaxLine));
    const auto semi = line.find(';');
    const std::vector<std::string> words = split(line.substr(0, semi), " \t\v\f");
    if (words.empty()) continue;  // a blank line, or a comment line
    // The docs allow tabs between words; LinuxCNC 2.9's reader (strtok on " ") does not.
    if (line.substr(0, semi).find('\t') != std::string_view::npos)
      notes.add("words separated by tabs (LinuxCNC's own reader separates words by spaces only)",
                "line " + std::to_string(line_no));
    const std::string comment = semi == std::string_view::npos ? std::string() : trim(line.substr(semi + 1));
    std::array<std::optional<double>, kWords.size()> value{};
    for (const std::string& w : words) {
      const auto letter = static_cast<char>(std::toupper(static_cast<unsigned char>(w[0])));
      const std::size_t slot = kWords.find(letter);
      if (slot == std::string_view::npos)
        throw line_error(source, line_no,
                         "word " + in_quotes(w) +
                             " is not a tool-table word (T P D X Y Z A B C U V W I J Q, each with its number; "
                             "a comment starts with ';')");
      if (value[slot]) throw line_error(source, line_no, std::string("word ") + letter + " is given twice");
      const std::string_view num = std::string_view(w).substr(1);
      if (letter == 'T' || letter == 'P' || letter == 'Q') {
        const auto v = parse_int(num);
        if (!v) throw line_error(source, line_no, "word " + in_quotes(w) + ": " + letter + " takes a whole number");
        value[slot] = *v;
      } else {
        const auto v = parse_real(num);
        if (!v) throw line_error(source, line_no, "word " + in_quotes(w) + ": " + letter + " takes a finite number");
        value[slot] = *v;
      }
    }
    auto at = [&](char c) { return value[kWords.find(c)]; };
    if (!at('T')) throw line_error(source, line_no, "no T word (the tool number)");
    if (!at('P')) throw line_error(source, line_no, "no P word (the pocket; LinuxCNC needs one on every line)");
    const auto t = static_cast<int>(*at('T')), p = static_cast<int>(*at('P'));
    if (t < 0 || t > kMaxToolNumber)
      throw line_error(source, line_no,
                       "T" + std::to_string(t) + ": a tool number is in [0, " + std::to_string(kMaxToolNumber) + "]");
    if (p < 0 || p > kLinuxCncMaxPocket)
      throw line_error(source, line_no,
                       "P" + std::to_string(p) + ": a pocket is in [0, " + std::to_string(kLinuxCncMaxPocket) + "]");
    if (t == 0) {  // LinuxCNC's "no tool" (an empty spindle), not a tool
      notes.add("T0 is LinuxCNC's empty spindle, not a tool: left out", "line " + std::to_string(line_no));
      continue;
    }
    const std::string T = "T" + std::to_string(t);
    if (const auto seen = line_of.find(t); seen != line_of.end())
      throw line_error(source, line_no,
                       T + " is also line " + std::to_string(seen->second) + "; a tool number appears once");
    line_of.emplace(t, line_no);
    if (!at('D'))
      throw line_error(source, line_no, T + ": no D word (the diameter; millnet needs every tool's diameter)");
    if (!(*at('D') > 0))
      throw line_error(source, line_no, T + ": diameter D" + format_double(*at('D')) + " must be > 0");
    for (const char c : std::string_view("XYZABCUVW")) offsets = offsets || (at(c) && *at(c) != 0);
    for (const char c : std::string_view("IJQ")) lathe = lathe || (at(c) && *at(c) != 0);
    pockets = pockets || p != t;

    const CommentFacts f = read_comment(comment, k);
    Tool tool;
    tool.number = t;
    tool.diameter_mm = to_mm(*at('D'), k);
    tool.description = comment;
    tool.id = ids.make(f.name.empty() ? slug(comment) : f.name, "t" + std::to_string(t));
    tool.type = f.type.value_or(ToolType::Flat);
    if (!f.type) notes.add("no tool type in the comment (ball, bull, drill, end mill): taken as a flat end mill", T);
    if (tool.type == ToolType::Ball) tool.corner_radius_mm = tool.diameter_mm / 2;
    if (tool.type == ToolType::Bull) {
      if (!f.corner_mm)
        throw line_error(
            source, line_no,
            T + ": the comment names a bull nose but no corner radius (write it as r<radius>, e.g. 'bull r1')");
      tool.corner_radius_mm = *f.corner_mm;
    }
    tool.flutes = f.flutes.value_or(2);
    if (!f.flutes) notes.add("no flute count in the comment (e.g. '3F'): 2 flutes", T);
    tool.material = f.material.value_or(ToolMaterial::Carbide);
    if (!f.material) notes.add("no tool material in the comment (carbide, hss): carbide", T);
    tool.check(source + ":" + std::to_string(line_no));
    out.tools.push_back(std::move(tool));
    check_count(out.tools.size(), source);
  }
  if (out.tools.empty())
    throw file_error(source, "no tools (a LinuxCNC tool table has lines like 'T1 P1 D6 ;6 mm end mill')");
  if (units == LengthUnit::Inch) {
    notes.line("lengths read as inches (the machine's units) and converted to mm");
  } else {
    notes.line("lengths read as mm (a tool table is in the machine's units; --units inch for an inch machine)");
    const bool all_small =
        std::all_of(out.tools.begin(), out.tools.end(), [](const Tool& x) { return x.diameter_mm < 1; });
    if (all_small) notes.line("every diameter is below 1 mm: is this an inch machine's table? (--units inch)");
  }
  if (pockets) notes.line("pockets P are not kept (millnet keeps the tool number T; its export writes P = T)");
  if (offsets) notes.line("offsets X..W (tool lengths) are not kept: they stay in the machine's own table");
  if (lathe) notes.line("lathe words I, J, Q ignored");
  out.notes = notes.lines(source);
  return out;
}

ToolTableText linuxcnc_tool_table(const std::vector<Tool>& tools) {
  if (tools.empty()) throw Error("LinuxCNC tool table: no tools to write");
  std::vector<const Tool*> order;
  std::string unnumbered;
  std::size_t missing = 0;
  for (const Tool& t : tools) {
    if (t.number > 0) {
      order.push_back(&t);
    } else if (++missing <= 5) {
      unnumbered += (missing > 1 ? ", " : "") + in_quotes(t.id);
    }
  }
  if (missing > 0)
    throw Error("LinuxCNC tool table: " + std::to_string(missing) + " tool(s) without a number (T): " + unnumbered +
                (missing > 5 ? ", ..." : "") + "; give each a \"number\" in its tool library");
  std::stable_sort(order.begin(), order.end(), [](const Tool* a, const Tool* b) { return a->number < b->number; });
  ToolTableText out;
  std::string body;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Tool& t = *order[i];
    const std::string T = "T" + std::to_string(t.number);
    if (i > 0 && order[i - 1]->number == t.number)
      throw Error("LinuxCNC tool table: " + T + " is both " + in_quotes(order[i - 1]->id) + " and " + in_quotes(t.id) +
                  "; a tool number appears once");
    if (t.number > kLinuxCncMaxPocket)
      throw Error("LinuxCNC tool table: " + T + " (" + in_quotes(t.id) +
                  "): the export writes P = T and LinuxCNC's pockets go up to " + std::to_string(kLinuxCncMaxPocket));
    t.check("LinuxCNC tool table: " + T);
    if (t.length_offset > 0 && t.length_offset != t.number)
      out.notes.push_back(T + " " + t.id + ": length offset H" + std::to_string(t.length_offset) +
                          " not written (a LinuxCNC table has one length per tool: G43 H" + std::to_string(t.number) +
                          " reads this tool's)");
    // The comment names what read_linuxcnc_tool_table reads back (type, corner radius, flutes,
    // material), and the id as far as LinuxCNC's 39 characters allow.
    std::string facts = type_word(t.type);
    if (t.type == ToolType::Bull) facts += " r" + short_number(t.corner_radius_mm);
    facts += " " + std::to_string(t.flutes) + "F";
    if (t.material == ToolMaterial::HSS) facts += " hss";  // carbide, the reader's default, saves room
    std::string id;
    for (const char c : t.id)
      id += static_cast<unsigned char>(c) <= 0x20 || static_cast<unsigned char>(c) >= 0x7f ? '_' : c;
    const std::size_t room = kLinuxCncMaxComment - std::min(kLinuxCncMaxComment, facts.size() + 2);
    if (id.size() > room) {
      out.notes.push_back(T + " " + t.id + ": id shortened to '" + id.substr(0, room) +
                          "' in the comment (LinuxCNC keeps " + std::to_string(kLinuxCncMaxComment) + " characters)");
      id.resize(room);
    }
    body += T + " P" + std::to_string(t.number) + " D" + format_double(t.diameter_mm) + " Z0 ;" +
            (id.empty() ? facts : id + ": " + facts) + "\n";
  }
  out.text = "; millnet tool table for LinuxCNC, mm: " + std::to_string(order.size()) +
             " tools, P = T, Z0 until each length is measured at the machine\n" + body;
  return out;
}

}  // namespace millnet::tooling::io
