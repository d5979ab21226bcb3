#pragma once
// Tool library and material table (configs/tools.json, configs/materials.json, compiled into the
// binary; a shop's own files named by /cutting/tools_file and /cutting/materials_file add to them),
// and the cutting data a command runs at, with where each figure came from (issue 17).
// JSON stops here: the modules get tooling::Tool / Material and the feeds in their parameter structs.
#include "config.hpp"

#include "millnet/tooling/cutter.hpp"
#include "millnet/tooling/cutting.hpp"

#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

struct ToolLibrary {
  std::vector<tooling::Tool> tools;
  std::vector<tooling::Material> materials;
  std::string tools_source = "built-in configs/tools.json", materials_source = "built-in configs/materials.json";
  /// Per tool (same order as `tools`): "built-in configs/tools.json" or the /cutting/tools_file it came from.
  std::vector<std::string> tool_sources;
  /// Throws millnet::Error "<what>: unknown tool id 'x' (did you mean 'y'?; <n> tools in <source>)".
  [[nodiscard]] const tooling::Tool& tool(const std::string& id, const std::string& what) const;
  [[nodiscard]] const tooling::Material& material(const std::string& id, const std::string& what) const;
};

/// The built-in library plus the config's /cutting/tools_file and /cutting/materials_file.
[[nodiscard]] ToolLibrary tool_library(const Json& config);

/// The tools of the machine's tool table (`millnet tools export`): every tool of the library, except a
/// built-in tool whose number a tool of /cutting/tools_file has (the shop's file describes its
/// machine; the built-in tools are examples): each one left out is named in `notes`.
[[nodiscard]] std::vector<tooling::Tool> machine_tools(const ToolLibrary& lib, std::vector<std::string>& notes);

/// Checks a tools.json / materials.json document against its schema (errors name `source` and the key).
void check_tool_library(Json& doc, const std::string& source);
void check_material_table(Json& doc, const std::string& source);

/// /cutting and /machine as the modules' structs.
struct CuttingSettings {
  bool library_feeds = true;  ///< /cutting/feeds == "library"
  std::string material_id;
  std::string material_key;   ///< "--material" | "/cutting/material": where the id was given
  std::string material_from;  ///< "flag --material" | "config /cutting/material"
  tooling::MachineLimits machine;
  tooling::FeedFactors factors;
  tooling::Overrides overrides;
  int inline_flutes = 2;
  tooling::ToolMaterial inline_material = tooling::ToolMaterial::Carbide;
  double inline_stickout_mm = 40;  ///< /cutting/inline_stickout_mm
};
/// `material_flag` = --material (else /cutting/material, written or default).
[[nodiscard]] CuttingSettings cutting_settings(const Json& config, const std::optional<std::string>& material_flag);

/// A tool given inline by its geometry, with the inline flutes and tool material of /cutting, and
/// its reach (issue 38: an inline tool was never checked against the holder): the stick-out, flute
/// length and holder of the library's tool of that type, diameter and corner radius (the longest
/// stick-out when several), else /cutting/inline_stickout_mm.
[[nodiscard]] tooling::Tool inline_tool(tooling::ToolType type, double diameter_mm, double corner_radius_mm,
                                        const CuttingSettings& cs, const ToolLibrary& library);

/// The finishing cutter's shape of a library tool (flat, ball or bull; a drill is refused).
[[nodiscard]] tooling::Cutter cutter_of(const tooling::Tool& tool);

/// A figure and where it came from, for the metrics' "cutting_data" object.
struct Figure {
  double value = 0;
  std::string source;
};

/// The cutting data a program runs at: the library's figures, then each figure the user wrote
/// (config key, pocket-file key or flag) in its place, every one with its source.
struct CuttingRecord {
  tooling::Tool tool;
  std::string tool_from;  ///< "flag --tool" | "config /pocket/tool" | "flag --tool-diameter" | …
  std::string material_id, material_from;
  bool library_feeds = true;
  tooling::CuttingData data;                            ///< valid when library_feeds
  std::vector<std::pair<std::string, Figure>> figures;  ///< "spindle_rpm", "feed_half", … in order
  [[nodiscard]] Json to_json() const;
  /// Header comments: the tool, the material and the figures (empty in fixed mode with an inline
  /// tool, so the 1995 preset's programs stay byte for byte what they were).
  [[nodiscard]] std::vector<std::string> header() const;
};

}  // namespace millnet::app
