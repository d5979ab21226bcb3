#pragma once
// What every reader of outside JSON (configs, pockets, models, manifests) does before and after the
// JSON library parses: a cap on nesting, checked on the text first (a value nested 70,000 levels
// deep overflowed the stack of every recursive walk over it: printing, checking, copying; issue 15,
// tests/corpus/cli/config_nested_70000_levels.args), and the library's message without its
// "[json.exception.…]" prefix. No JSON library here: core stays free of it.
#include "millnet/core/error.hpp"

#include <string>
#include <string_view>

namespace millnet {

/// Deepest nesting of arrays/objects accepted in an input JSON file (configs, pockets, models,
/// manifests nest 4–6 levels).
inline constexpr int kMaxJsonDepth = 64;

/// Throws millnet::Error "<source>:<line>: JSON nested deeper than 64 levels (column c)" when the
/// text opens more than max_depth arrays/objects at once. Brackets inside strings do not count.
/// O(|text|), no allocation.
inline void check_json_nesting(std::string_view text, const std::string& source, int max_depth = kMaxJsonDepth) {
  int depth = 0;
  long line = 1;
  std::size_t line_start = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
    }
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth)
        throw line_error(source, line,
                         "JSON nested deeper than " + std::to_string(max_depth) + " levels (column " +
                             std::to_string(i - line_start + 1) + ")");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

/// The JSON library's message for the user: "[json.exception.out_of_range.406] number overflow
/// parsing '1e309'" → "number overflow parsing '1e309'".
inline std::string json_error_text(std::string_view what) {
  if (!what.empty() && what[0] == '[')
    if (const auto end = what.find("] "); end != std::string_view::npos) what.remove_prefix(end + 2);
  return std::string(what);
}

}  // namespace millnet
