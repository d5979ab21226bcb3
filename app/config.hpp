#pragma once
// Configs: JSON files checked against configs/schema/millnet.schema.json (a JSON-Schema subset:
// type, properties, additionalProperties:false, items, enum, minimum, maximum, default,
// description, and "format": "path"). Validation is strict: an unknown key or a wrong type is an
// error naming the key path (e.g. "/train/alpha_candidates: expected an integer, got \"x\"").
// Defaults from the schema are filled in, and every "path" value is resolved against the folder of
// the config file. JSON stops here: commands convert the checked config to modules' parameter structs.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace millnet::pocket {
struct PocketFile;
}

namespace millnet::app {

using Json = nlohmann::json;

/// The schema compiled into the binary.
[[nodiscard]] const Json& schema();

/// Reads, validates, fills defaults and resolves paths; throws millnet::Error naming file and key.
[[nodiscard]] Json load_config(const std::filesystem::path& path);

/// The all-defaults config (paths resolved against `base`), for commands run without --config.
[[nodiscard]] Json default_config(const std::filesystem::path& base);

/// Validates `config` (in place: defaults filled, paths resolved against `base`), `source` names it in errors.
void check_config(Json& config, const std::filesystem::path& base, const std::string& source);

/// The numbers a pocket file carries (tool_diameter, feed_slot, …) checked against the ranges of
/// their /pocket/… keys in the schema, as if the config had them: "<source>: /feed_slot: must be > 0, got 0".
void check_pocket_file(const pocket::PocketFile& file, const std::string& source);

/// Validates `doc` against `rule` (a schema of the same subset), filling defaults and resolving
/// "path" values against `base`; errors name `source` and the key.
void check_against(Json& doc, const Json& rule, const std::filesystem::path& base, const std::string& source);

/// Reads a JSON file with clear parse errors (file:line:column).
[[nodiscard]] Json read_json(const std::filesystem::path& path);

}  // namespace millnet::app
