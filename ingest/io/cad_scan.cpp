// Structural pre-scan of STEP and IGES files (see cad_scan.hpp): one linear pass, explicit stacks,
// no recursion, so that nothing a file nests or refers to can exhaust the stack here either.
#include "cad_scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace millnet::ingest::detail {

namespace {

bool is_alpha(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

/// "#16 → #17 → #18 → #16", at most 6 ids before "…".
std::string id_chain(const std::vector<std::uint64_t>& ids) {
  std::string s;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (k == 6 && ids.size() > 7) {
      s += " → … → #" + std::to_string(ids.back());
      break;
    }
    s += (k ? " → #" : "#") + std::to_string(ids[k]);
  }
  return s;
}

/// A directed graph on 0..n-1 in compressed rows; finds one cycle (iteratively). Returns the node
/// indices of the cycle, the first one repeated at its end, or nothing.
std::vector<std::uint32_t> find_cycle(std::size_t n, const std::vector<std::uint32_t>& begin,
                                      const std::vector<std::uint32_t>& adj) {
  std::vector<std::uint8_t> colour(n, 0);                      // 0 new, 1 on the stack, 2 done
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;  // node, next edge
  for (std::uint32_t root = 0; root < n; ++root) {
    if (colour[root]) continue;
    stack.push_back({root, begin[root]});
    colour[root] = 1;
    while (!stack.empty()) {  // O(n + edges) over all roots
      auto& [v, e] = stack.back();
      if (e == begin[v + 1]) {
        colour[v] = 2;
        stack.pop_back();
        continue;
      }
      const std::uint32_t w = adj[e++];
      if (colour[w] == 0) {
        colour[w] = 1;
        stack.push_back({w, begin[w]});
      } else if (colour[w] == 1) {
        std::vector<std::uint32_t> cycle;
        std::size_t k = stack.size();
        while (k > 0 && stack[k - 1].first != w) --k;
        for (std::size_t j = k - 1; j < stack.size(); ++j) cycle.push_back(stack[j].first);
        cycle.push_back(w);
        return cycle;
      }
    }
  }
  return {};
}

/// Compressed rows from (from, to) pairs over n nodes.
void compress(std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& edges,
              std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& adj) {
  begin.assign(n + 1, 0);
  for (const auto& e : edges) ++begin[e.first + 1];
  for (std::size_t k = 0; k < n; ++k) begin[k + 1] += begin[k];
  adj.assign(edges.size(), 0);
  std::vector<std::uint32_t> at(begin.begin(), begin.end() - 1);
  for (const auto& e : edges) adj[at[e.first]++] = e.second;
}

/// SI prefixes of ISO 10303-41 (si_prefix), as factors.
double si_prefix(std::string_view p) {
  static const std::pair<std::string_view, double> table[] = {
      {"EXA", 1e18},  {"PETA", 1e15},  {"TERA", 1e12},   {"GIGA", 1e9},   {"MEGA", 1e6},   {"KILO", 1e3},
      {"HECTO", 1e2}, {"DECA", 1e1},   {"DECI", 1e-1},   {"CENTI", 1e-2}, {"MILLI", 1e-3}, {"MICRO", 1e-6},
      {"NANO", 1e-9}, {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};
  for (const auto& [name, f] : table)
    if (p == name) return f;
  return 0;
}

struct Statement {
  std::uint64_t id = 0;
  std::size_t line = 0;
  std::size_t begin = 0, end = 0;     ///< byte range of the whole instance
  std::vector<std::string> partials;  ///< keyword of a simple instance, or each partial of a complex one
  /// References in order, with the partial (index into partials) whose parameters hold them.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> refs;
};

bool has_partial(const Statement& s, std::string_view kw) {
  return std::find(s.partials.begin(), s.partials.end(), kw) != s.partials.end();
}

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

/// The first two references held by the partial `kw` (relating, related / rep_1, rep_2).
bool first_two_refs(const Statement& s, std::size_t partial, std::uint64_t& a, std::uint64_t& b) {
  int found = 0;
  for (const auto& [id, p] : s.refs) {
    if (p != partial) continue;
    (found == 0 ? a : b) = id;
    if (++found == 2) return true;
  }
  return false;
}

class StepScanner {
  struct Relation {  ///< a usage (relating → related product) or a representation relationship
    std::uint64_t a, b, entity;
    std::size_t line;
    bool usage;
  };
  struct Where {  ///< an entity's bytes and line
    std::size_t begin, end, line;
  };

public:
  explicit StepScanner(std::string_view b) : b_(b) {}

  CadScan run() {
    lex();
    if (!out_.refusal.empty()) return out_;
    link();
    if (!out_.refusal.empty()) return out_;
    units();
    return out_;
  }

private:
  void syntax(const std::string& what) {
    if (out_.syntax_errors++ == 0) out_.first_syntax_error = "line " + std::to_string(line_) + ": " + what;
  }
  void refuse(const std::string& what) {
    if (out_.refusal.empty()) out_.refusal = what;
  }
  std::string entity_here() const { return cur_.id ? " (entity #" + std::to_string(cur_.id) + ")" : ""; }

  /// Tokens, nesting and references of every statement. O(bytes).
  void lex() {
    new_statement(0);
    while (lx_.i < b_.size())
      if (!token()) return;
    if (lx_.depth > 0) syntax("the file ends inside " + std::to_string(lx_.depth) + " open '('");
  }

  void new_statement(std::size_t at) {
    cur_ = Statement{};
    cur_.begin = at;
    lx_.in_entity = lx_.after_equals = lx_.complex = lx_.seen_token = false;
    lx_.pending_id = 0;
    lx_.partial_depth = -1;
  }

  /// The token at lx_.i; false when the scan stops (a refusal, or a string that never closes).
  bool token() {
    const std::size_t n = b_.size();
    std::size_t& i = lx_.i;
    const char c = b_[i];
    if (c == '\n') {
      ++line_;
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
    } else if (c == '/' && i + 1 < n && b_[i + 1] == '*') {
      comment();
    } else if (c == '\'') {
      return quoted_string();
    } else if (c == '"') {  // binary literal
      const std::size_t close = b_.find('"', i + 1);
      if (close == std::string_view::npos) {
        syntax("a binary literal \" is not closed" + entity_here());
        return false;
      }
      i = close + 1;
      lx_.seen_token = true;
    } else if (c == '(') {
      return open_parenthesis();
    } else if (c == ')') {
      if (lx_.depth == 0)
        syntax("a ')' closes nothing" + entity_here());
      else
        --lx_.depth;
      if (lx_.depth < lx_.partial_depth) lx_.partial_depth = -1;
      ++i;
    } else if (c == ';') {
      end_statement();
    } else if (c == '#') {
      reference();
    } else if (c == '=') {
      if (lx_.pending_id != 0 && !lx_.in_entity && lx_.depth == 0) {
        lx_.in_entity = true;
        lx_.after_equals = true;
        lx_.seen_token = false;
        cur_.id = lx_.pending_id;
        cur_.line = line_;
      }
      ++i;
    } else if (is_alpha(c)) {
      keyword();
    } else if (c == '.' && i + 1 < n && is_alpha(b_[i + 1])) {  // enumeration .T. / .MILLI.
      const std::size_t close = b_.find('.', i + 1);
      i = close == std::string_view::npos ? n : close + 1;
      lx_.seen_token = true;
    } else if (is_digit(c) ||
               ((c == '-' || c == '+' || c == '.') && i + 1 < n && (is_digit(b_[i + 1]) || b_[i + 1] == '.'))) {
      return number();
    } else {
      lx_.seen_token = true;  // ',', '$', '*' and anything else
      ++i;
    }
    return true;
  }

  void comment() {
    std::size_t& i = lx_.i;
    const std::size_t n = b_.size();
    const std::size_t close = b_.find("*/", i + 2);
    const std::size_t stop = close == std::string_view::npos ? n : close + 2;
    line_ += static_cast<std::size_t>(
        std::count(b_.begin() + static_cast<std::ptrdiff_t>(i), b_.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
    if (close == std::string_view::npos) syntax("a comment /* is not closed");
    i = stop;
  }

  /// A string: '' is a quote inside it.
  bool quoted_string() {
    std::size_t& i = lx_.i;
    const std::size_t n = b_.size();
    std::size_t k = i + 1;
    const std::size_t start_line = line_;
    while (k < n) {
      if (b_[k] == '\n') ++line_;
      if (b_[k] == '\'') {
        if (k + 1 < n && b_[k + 1] == '\'') {
          k += 2;
          continue;
        }
        break;
      }
      ++k;
    }
    if (k >= n) {
      line_ = start_line;
      syntax("a string ' is not closed" + entity_here());
      return false;
    }
    i = k + 1;
    lx_.seen_token = true;
    return true;
  }

  bool open_parenthesis() {
    ++lx_.depth;
    if (lx_.depth > out_.max_depth) out_.max_depth = lx_.depth;
    if (lx_.depth > kMaxStepNesting) {
      refuse("line " + std::to_string(line_) + ": parentheses nested more than " + std::to_string(kMaxStepNesting) +
             " deep" + entity_here() + " (Open CASCADE's reader recurses per level)");
      return false;
    }
    if (lx_.in_entity && lx_.after_equals && !lx_.seen_token) lx_.complex = true;  // "#1 = ( A() B() )"
    lx_.seen_token = true;
    ++lx_.i;
    return true;
  }

  void end_statement() {
    if (lx_.depth > 0) {
      syntax(std::string("the statement ends with ") + std::to_string(lx_.depth) + " '(' not closed" + entity_here());
      lx_.depth = 0;
    }
    cur_.end = lx_.i + 1;
    if (lx_.in_entity) commit();
    ++lx_.i;
    new_statement(lx_.i);
  }

  /// "#12": an instance's name before its '=', else a reference of the current partial.
  void reference() {
    std::size_t& i = lx_.i;
    const std::size_t n = b_.size();
    std::size_t k = i + 1;
    while (k < n && is_digit(b_[k])) ++k;
    const std::size_t digits = k - i - 1;
    if (digits == 0 || digits > 18) {
      syntax("'#' not followed by an entity number of 1 to 18 digits" + entity_here());
      i = std::max(k, i + 1);
      return;
    }
    const std::uint64_t id = std::strtoull(std::string(b_.substr(i + 1, digits)).c_str(), nullptr, 10);
    if (!lx_.seen_token && !lx_.in_entity && lx_.depth == 0) {
      lx_.pending_id = id;
    } else if (lx_.in_entity) {
      const auto partial = static_cast<std::uint32_t>(cur_.partials.empty() ? 0 : cur_.partials.size() - 1);
      cur_.refs.push_back({id, partial});
    }
    lx_.seen_token = true;
    i = k;
  }

  void keyword() {
    std::size_t& i = lx_.i;
    const std::size_t n = b_.size();
    std::size_t k = i;
    std::string kw;
    while (k < n && (is_alpha(b_[k]) || is_digit(b_[k]) || b_[k] == '-')) kw += upper(b_[k++]);
    if (lx_.in_entity && lx_.partial_depth < 0 &&
        ((!lx_.complex && lx_.depth == 0) || (lx_.complex && lx_.depth == 1))) {
      cur_.partials.push_back(kw);
      lx_.partial_depth = lx_.depth + 1;
    }
    lx_.seen_token = true;
    i = k;
  }

  /// A number; only a long mantissa or a 3-digit exponent can overflow a double: those are parsed.
  bool number() {
    std::size_t& i = lx_.i;
    const std::size_t n = b_.size();
    const char c = b_[i];
    std::size_t k = i + 1;
    std::size_t mantissa = is_digit(c) ? 1U : 0U, exponent = 0;
    while (k < n && (is_digit(b_[k]) || b_[k] == '.')) mantissa += is_digit(b_[k++]) ? 1U : 0U;
    if (k < n && (b_[k] == 'E' || b_[k] == 'e')) {
      ++k;
      if (k < n && (b_[k] == '+' || b_[k] == '-')) ++k;
      while (k < n && is_digit(b_[k])) ++k, ++exponent;
    }
    if (mantissa > 300 || exponent >= 3) {
      const std::string num(b_.substr(i, k - i));
      const double v = std::strtod(num.c_str(), nullptr);
      if (!std::isfinite(v)) {
        refuse("line " + std::to_string(line_) + ": the number " + quote_bytes(num) + " does not fit a double" +
               entity_here());
        return false;
      }
    }
    lx_.seen_token = true;
    i = k;
    return true;
  }

  void commit() {
    const std::uint32_t index = static_cast<std::uint32_t>(ids_.size());
    if (!index_.emplace(cur_.id, index).second) {
      const std::size_t keep = line_;
      line_ = cur_.line;
      syntax("entity #" + std::to_string(cur_.id) + " is defined twice");
      line_ = keep;
      return;
    }
    ids_.push_back(cur_.id);
    lines_.push_back(cur_.line);
    ref_begin_.push_back(static_cast<std::uint32_t>(refs_.size()));
    for (const auto& r : cur_.refs) refs_.push_back(r.first);
    if (has_partial(cur_, "ADVANCED_FACE") || has_partial(cur_, "FACE_SURFACE")) ++out_.faces;
    for (std::size_t p = 0; p < cur_.partials.size(); ++p) {
      const std::string& kw = cur_.partials[p];
      std::uint64_t a = 0, b = 0;
      const bool usage = ends_with(kw, "USAGE_OCCURRENCE") || kw == "ASSEMBLY_COMPONENT_USAGE" ||
                         kw == "PRODUCT_DEFINITION_USAGE" || kw == "QUANTIFIED_ASSEMBLY_COMPONENT_USAGE";
      if ((usage || ends_with(kw, "REPRESENTATION_RELATIONSHIP")) && first_two_refs(cur_, p, a, b))
        relations_.push_back({a, b, cur_.id, cur_.line, usage});
    }
    if (has_partial(cur_, "LENGTH_UNIT") || has_partial(cur_, "LENGTH_MEASURE_WITH_UNIT"))
      unit_statements_[cur_.id] = {cur_.begin, cur_.end, cur_.line};
    for (std::size_t p = 0; p < cur_.partials.size(); ++p)
      if (cur_.partials[p] == "GLOBAL_UNIT_ASSIGNED_CONTEXT")
        for (const auto& [id, partial] : cur_.refs)
          if (partial == p) context_units_.push_back(id);
  }

  /// References resolved; cycles among entities and among assembly relations. O(entities + refs).
  void link() {
    out_.entities = ids_.size();
    ref_begin_.push_back(static_cast<std::uint32_t>(refs_.size()));
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(refs_.size());
    for (std::uint32_t e = 0; e < ids_.size(); ++e)
      for (std::uint32_t r = ref_begin_[e]; r < ref_begin_[e + 1]; ++r) {
        const auto it = index_.find(refs_[r]);
        if (it == index_.end()) {
          if (out_.unresolved_references++ == 0)
            out_.first_unresolved_reference = "line " + std::to_string(lines_[e]) + ": entity #" +
                                              std::to_string(ids_[e]) + " refers to #" + std::to_string(refs_[r]) +
                                              ", which the file does not define";
          continue;
        }
        edges.push_back({e, it->second});
      }
    std::vector<std::uint32_t> begin, adj;
    compress(ids_.size(), edges, begin, adj);
    std::vector<std::uint32_t> cycle = find_cycle(ids_.size(), begin, adj);
    if (!cycle.empty()) {
      const std::uint32_t first = cycle.front();
      if (cycle.size() == 2)
        refuse("line " + std::to_string(lines_[first]) + ": entity #" + std::to_string(ids_[first]) +
               " refers to itself");
      else {
        std::vector<std::uint64_t> chain;
        for (const std::uint32_t k : cycle) chain.push_back(ids_[k]);
        refuse("line " + std::to_string(lines_[first]) + ": entities " + id_chain(chain) +
               " refer to each other in a cycle");
      }
      return;
    }
    // Assembly structure: a product that contains itself, a representation related to itself.
    edges.clear();
    for (const auto& r : relations_) {
      const auto a = index_.find(r.a), b = index_.find(r.b);
      if (a == index_.end() || b == index_.end()) continue;
      edges.push_back({a->second, b->second});
    }
    compress(ids_.size(), edges, begin, adj);
    cycle = find_cycle(ids_.size(), begin, adj);
    if (!cycle.empty()) {
      std::vector<std::uint64_t> chain;
      for (const std::uint32_t k : cycle) chain.push_back(ids_[k]);
      // The relation that closes the cycle, for the message.
      const Relation* closing = nullptr;
      for (const auto& r : relations_)
        if (r.a == chain[chain.size() - 2] && r.b == chain.back()) closing = &r;
      const std::string what =
          closing && closing->usage ? "a product is a component of itself" : "a representation is related to itself";
      refuse("line " + std::to_string(closing ? closing->line : lines_[cycle.front()]) + ": " + what + " (" +
             (closing ? "#" + std::to_string(closing->entity) + ": " : "") + id_chain(chain) + ")");
    }
  }

  /// mm per unit of a LENGTH_UNIT / LENGTH_MEASURE_WITH_UNIT entity; 0 = not understood.
  double unit_mm(std::uint64_t id, int hops) const {
    const auto it = unit_statements_.find(id);
    if (it == unit_statements_.end() || hops > 8) return 0;
    const auto [begin, end, line] = it->second;
    if (end - begin > 4096) return 0;
    std::string t;
    for (std::size_t k = begin; k < end; ++k)
      if (b_[k] != ' ' && b_[k] != '\n' && b_[k] != '\r' && b_[k] != '\t') t += upper(b_[k]);
    auto ref_after = [&](std::size_t from) -> std::uint64_t {
      const std::size_t h = t.find('#', from);
      if (h == std::string::npos) return 0;
      return std::strtoull(t.c_str() + h + 1, nullptr, 10);
    };
    if (const std::size_t si = t.find("SI_UNIT("); si != std::string::npos) {
      const std::size_t comma = t.find(',', si);
      if (comma == std::string::npos || t.compare(comma + 1, 7, ".METRE.") != 0) return 0;
      const std::string prefix = t.substr(si + 8, comma - si - 8);
      if (prefix == "$") return 1000;
      if (prefix.size() < 3 || prefix.front() != '.' || prefix.back() != '.') return 0;
      return 1000 * si_prefix(std::string_view(prefix).substr(1, prefix.size() - 2));
    }
    if (const std::size_t cb = t.find("CONVERSION_BASED_UNIT("); cb != std::string::npos)
      return unit_mm(ref_after(cb), hops + 1);
    if (const std::size_t lm = t.find("LENGTH_MEASURE("); lm != std::string::npos) {
      const double value = std::strtod(t.c_str() + lm + 15, nullptr);
      const std::size_t close = t.find(')', lm);
      const double base = close == std::string::npos ? 0 : unit_mm(ref_after(close), hops + 1);
      return value * base;
    }
    return 0;
  }

  bool is_length_unit(const Where& where) const {
    return b_.substr(where.begin, where.end - where.begin).find("LENGTH_UNIT") != std::string_view::npos;
  }

  /// Every length unit the file defines within [kMinUnitMm, kMaxUnitMm]; the one its unit
  /// contexts assign. O(unit entities).
  void units() {
    for (const auto& [id, where] : unit_statements_) {  // in entity order
      if (!is_length_unit(where)) continue;
      const double mm = unit_mm(id, 0);
      if (mm == 0) continue;  // not understood: Open CASCADE decides
      if (!(mm >= kMinUnitMm && mm <= kMaxUnitMm)) {
        refuse("line " + std::to_string(where.line) + ": the length unit #" + std::to_string(id) + " is " + fmt(mm) +
               " mm, outside " + fmt(kMinUnitMm) + " to " + fmt(kMaxUnitMm) + " mm");
        return;
      }
    }
    for (const std::uint64_t id : context_units_) {
      const auto it = unit_statements_.find(id);
      if (it == unit_statements_.end() || !is_length_unit(it->second)) continue;
      out_.unit_mm = unit_mm(id, 0);
      break;
    }
  }

  std::string_view b_;
  std::size_t line_ = 1;
  CadScan out_;
  /// The lexer's place: byte, nesting, and where the current statement stands.
  struct LexState {
    std::size_t i = 0;
    int depth = 0;
    bool in_entity = false, after_equals = false, complex = false, seen_token = false;
    std::uint64_t pending_id = 0;  ///< "#12" at a statement's start, before its '='
    int partial_depth = -1;        ///< depth at which the current partial's parameters open
  };
  LexState lx_;
  Statement cur_;
  std::vector<std::uint64_t> ids_;
  std::vector<std::size_t> lines_;
  std::vector<std::uint32_t> ref_begin_;
  std::vector<std::uint64_t> refs_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  std::vector<Relation> relations_;
  std::map<std::uint64_t, Where> unit_statements_;
  std::vector<std::uint64_t> context_units_;  ///< units GLOBAL_UNIT_ASSIGNED_CONTEXTs assign
};

/// An 8-column IGES integer field ("" or blanks = 0); false when it is not an integer.
bool iges_int(std::string_view field, long& v) {
  std::size_t a = 0, e = field.size();
  while (a < e && field[a] == ' ') ++a;
  while (e > a && field[e - 1] == ' ') --e;
  v = 0;
  if (a == e) return true;
  bool neg = false;
  if (field[a] == '-' || field[a] == '+') neg = field[a++] == '-';
  if (a == e) return false;
  for (; a < e; ++a) {
    if (!is_digit(field[a])) return false;
    v = v * 10 + (field[a] - '0');
  }
  if (neg) v = -v;
  return true;
}

}  // namespace

std::string quote_bytes(std::string_view s, std::size_t max_chars) {
  std::string out;
  std::size_t shown = 0;
  for (const char ch : s) {
    if (shown == max_chars) {
      out += "… (" + std::to_string(s.size()) + " characters)";
      return out;
    }
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

CadScan scan_step(std::string_view bytes) { return StepScanner(bytes).run(); }

CadScan scan_iges(std::string_view b) {
  CadScan out;
  std::vector<long> type, transform;  // per directory entry (2 lines each)
  std::size_t d_lines = 0, line = 0, pos = 0;
  std::string_view first;   // the first line of the entry being read
  while (pos < b.size()) {  // O(bytes)
    std::size_t end = b.find('\n', pos);
    if (end == std::string_view::npos) end = b.size();
    std::string_view l = b.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l.size() < 73 || l[72] != 'D') continue;
    if (d_lines++ % 2 == 0) {
      first = l;
      continue;
    }
    long t = 0, tr = 0;
    if (!iges_int(first.substr(0, 8), t) || !iges_int(first.substr(48, 8), tr)) {
      if (out.syntax_errors++ == 0)
        out.first_syntax_error = "line " + std::to_string(line - 1) + ": directory entry " +
                                 std::to_string(2 * type.size() + 1) + " has a field that is not an integer";
      t = 0;
      tr = 0;
    }
    type.push_back(t);
    transform.push_back(tr);
  }
  if (d_lines % 2 != 0 && out.syntax_errors++ == 0)
    out.first_syntax_error = "the directory section has an odd number of lines (" + std::to_string(d_lines) + ")";
  out.entities = type.size();
  for (const long t : type)
    if (t == 510 || t == 144 || t == 143) ++out.faces;
  // Transformation chains: each entry points at most at one matrix (a directory pointer 2k + 1).
  const std::size_t n = type.size();
  std::vector<long> next(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    const long p = transform[k];
    if (p == 0) continue;
    if (p < 0 || p % 2 == 0 || static_cast<std::size_t>(p / 2) >= n) {
      if (out.unresolved_references++ == 0)
        out.first_unresolved_reference = "directory entry " + std::to_string(2 * k + 1) +
                                         " points at transformation matrix " + std::to_string(p) +
                                         ", which the file does not define";
      continue;
    }
    next[k] = p / 2;
  }
  std::vector<std::uint8_t> state(n, 0);  // 0 new, 1 on the current walk, 2 done
  std::vector<std::size_t> walk;
  for (std::size_t k = 0; k < n; ++k) {  // O(n): each entry is walked once
    walk.clear();
    std::size_t v = k;
    while (state[v] == 0) {
      state[v] = 1;
      walk.push_back(v);
      if (next[v] < 0) break;
      v = static_cast<std::size_t>(next[v]);
    }
    if (state[v] == 1 && next[v] >= 0) {
      out.refusal = "directory entry " + std::to_string(2 * v + 1) +
                    ": its chain of transformation matrices (directory field 7) loops back to itself";
      return out;
    }
    for (const std::size_t w : walk) state[w] = 2;
  }
  return out;
}

}  // namespace millnet::ingest::detail
