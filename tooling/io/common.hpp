#pragma once
// What the tool-table readers share (private to tooling/io): bounds, numbers, ids, notes.
#include "millnet/tooling/io/tool_tables.hpp"

#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::tooling::io::detail {

/// Throws "<source>: <n> bytes; the limit is 8 MiB (a tool table)" for an input over kMaxToolFileBytes.
void check_size(std::size_t bytes, const std::string& source);
/// Throws "<source>: more than 10000 tools; the limit is 10000" once `count` exceeds kMaxImportedTools.
void check_count(std::size_t count, const std::string& source);

/// A whole decimal number ("6", "+0.5", ".125", "1e-3"); nullopt for anything else, NaN and ±inf included.
[[nodiscard]] std::optional<double> parse_real(std::string_view s);
/// A whole integer ("12", "+3"); nullopt for anything else or out of int's range.
[[nodiscard]] std::optional<int> parse_int(std::string_view s);

/// `v` in a unit of `mm_per_unit` mm, in mm; converted lengths are rounded to 1e-6 mm (0.25 in is
/// 6.35 mm, not 6.3500000000000005).
[[nodiscard]] double to_mm(double v, double mm_per_unit);

/// `s` for a one-line message: control characters as '?', at most 60 characters (then "...").
[[nodiscard]] std::string shown(std::string_view s);
/// "'" + shown(s) + "'".
[[nodiscard]] std::string in_quotes(std::string_view s);

/// A library id from a name: lower-case ASCII letters, digits and '.', other runs as one '-'
/// ("6 mm Bull Nose" → "6-mm-bull-nose"), at most 48 characters; "" when nothing is left.
[[nodiscard]] std::string slug(std::string_view name);

/// Unique ids within one import: the first free of base, base-2, base-3, …
class IdMaker {
public:
  /// `base` made unique; `fallback` when base is empty.
  std::string make(const std::string& base, const std::string& fallback);

private:
  std::set<std::string> used_;
};

/// Assumptions made per tool, said once each: "<source>: <what>: T1, T2, … (n tools)".
class Notes {
public:
  void add(const std::string& what, const std::string& who);
  void line(const std::string& text);  ///< a note of its own
  [[nodiscard]] std::vector<std::string> lines(const std::string& source) const;

private:
  std::vector<std::string> order_;
  std::map<std::string, std::vector<std::string>> who_;
  std::vector<std::string> single_;
};

/// "T<number>" or the tool's id: how notes name a tool.
[[nodiscard]] std::string who(const Tool& t);

}  // namespace millnet::tooling::io::detail
