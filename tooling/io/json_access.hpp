#pragma once
// JSON for the FreeCAD and Fusion readers (private to tooling/io): parsing with one-line errors, and
// typed access naming the JSON pointer of what is wrong.
#include "common.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace millnet::tooling::io::detail {

using Json = nlohmann::json;

/// Parses `text` (bounded, nesting capped) or throws "<source>: malformed JSON: <where and what>".
[[nodiscard]] Json parse_json(std::string_view text, const std::string& source);

/// `obj[key]` when present and not null; throws "<source>: <at>/<key>: expected <what>" when `obj`
/// is not an object. The typed getters below throw "<source>: <at>/<key>: expected …, got …".
[[nodiscard]] const Json* member(const Json& obj, const std::string& key, const std::string& source,
                                 const std::string& at);
[[nodiscard]] std::optional<double> opt_number(const Json& obj, const std::string& key, const std::string& source,
                                               const std::string& at);
[[nodiscard]] std::optional<std::string> opt_string(const Json& obj, const std::string& key, const std::string& source,
                                                    const std::string& at);
/// A whole number (JSON integer, or a number with no fraction) in [lo, hi].
[[nodiscard]] std::optional<int> opt_int(const Json& obj, const std::string& key, const std::string& source,
                                         const std::string& at, int lo, int hi);

/// The value as the message shows it: "\"6 furlongs\"", "true", "[…]".
[[nodiscard]] std::string shown_json(const Json& v);

}  // namespace millnet::tooling::io::detail
