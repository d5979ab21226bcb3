// millnet tools import FILE --format linuxcnc|freecad|fusion [--units mm|inch] --out tools.json
// millnet tools export --format linuxcnc [--config FILE] --out tool.tbl
// (issue 40: a shop's tool table in, a LinuxCNC tool table out; the formats: tooling/io/tool_tables.hpp)
#include "cli.hpp"
#include "cutting.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/tooling/io/tool_tables.hpp"

#include <cmath>
#include <cstdint>
#include <memory>

namespace millnet::app {
namespace {

struct ToolsOpts {
  Common import_common, export_common;
  std::string file, import_format, export_format, out_library, out_table;
  std::optional<std::string> units;
};

/// --out of a file: refuses an empty or blank path (which would write into the current folder).
CLI::Validator output_file() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.find_first_not_of(" \t\r\n") == std::string::npos)
          return "expected a file to write, got an empty path";
        return std::string();
      },
      "FILE");
}

/// A figure as configs/tools.json writes it: 6, not 6.0.
nlohmann::ordered_json figure(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return static_cast<std::int64_t>(v);
  return v;
}

/// A tool as a row of configs/tools.json (configs/schema/tools.schema.json); the keys of issue 40 and
/// a drill's point angle only when stated.
nlohmann::ordered_json tool_row(const tooling::Tool& t) {
  nlohmann::ordered_json j;
  j["id"] = t.id;
  j["description"] = t.description;
  j["type"] = tooling::to_string(t.type);
  j["diameter"] = figure(t.diameter_mm);
  j["corner_radius"] = figure(t.corner_radius_mm);
  j["flutes"] = t.flutes;
  j["flute_length"] = figure(t.flute_length_mm);
  j["stickout"] = figure(t.stickout_mm);
  j["tool_material"] = tooling::to_string(t.material);
  j["max_rpm"] = figure(t.max_rpm);
  if (t.type == tooling::ToolType::Drill) j["point_angle"] = figure(t.point_angle_deg);
  if (t.number > 0) j["number"] = t.number;
  if (t.length_offset > 0) j["length_offset"] = t.length_offset;
  if (t.holder_diameter_mm > 0) j["holder_diameter"] = figure(t.holder_diameter_mm);
  if (t.holder_length_mm > 0) j["holder_length"] = figure(t.holder_length_mm);
  return j;
}

const char* format_name(tooling::io::ToolFormat f) {
  switch (f) {
    case tooling::io::ToolFormat::LinuxCnc: return "a LinuxCNC tool table";
    case tooling::io::ToolFormat::FreeCad: return "FreeCAD ToolBits";
    case tooling::io::ToolFormat::Fusion: return "a Fusion 360 tool library";
  }
  return "?";
}

int run_import(const ToolsOpts& o) {
  (void)setup(o.import_common);
  const auto format = tooling::io::parse_tool_format(o.import_format);
  if (o.units && format != tooling::io::ToolFormat::LinuxCnc)
    throw Error("--units applies to --format linuxcnc (FreeCAD and Fusion 360 files carry their units)");
  const auto units = o.units == "inch" ? tooling::io::LengthUnit::Inch : tooling::io::LengthUnit::Mm;
  const tooling::io::ToolImport imported = tooling::io::import_tool_file(o.file, format, units);
  nlohmann::ordered_json doc;
  std::string comment = "Imported from " + o.file + " (" + format_name(format) + ") by millnet tools import.";
  if (!imported.notes.empty()) comment += " Assumed:";
  for (const std::string& n : imported.notes)  // the comment names the file once
    comment += " " + (n.rfind(o.file + ": ", 0) == 0 ? n.substr(o.file.size() + 2) : n) + ";";
  if (comment.back() == ';') comment.back() = '.';
  doc["comment"] = comment;
  doc["tools"] = nlohmann::ordered_json::array();
  for (const tooling::Tool& t : imported.tools) doc["tools"].push_back(tool_row(t));
  const std::string text = doc.dump(1) + "\n";
  // What is written is what `/cutting/tools_file` reads: checked by the same schema first.
  Json check = Json::parse(text);
  check_tool_library(check, o.out_library);
  write_file_atomic(o.out_library, text);
  for (const std::string& n : imported.notes) info("note: " + n);
  info("tools import: " + std::to_string(imported.tools.size()) + " tools from " + o.file + " -> " + o.out_library);
  return 0;
}

int run_export(const ToolsOpts& o) {
  const Json config = setup(o.export_common);
  (void)tooling::io::parse_tool_format(o.export_format);  // linuxcnc: the only table written
  const ToolLibrary lib = tool_library(config);
  std::vector<std::string> notes;
  const std::vector<tooling::Tool> tools = machine_tools(lib, notes);
  const tooling::io::ToolTableText table = tooling::io::linuxcnc_tool_table(tools);
  write_file_atomic(o.out_table, table.text);
  for (const std::string& n : notes) info("note: " + n);
  for (const std::string& n : table.notes) info("note: " + n);
  info("tools export: " + std::to_string(tools.size()) + " tools of " + lib.tools_source + " -> " + o.out_table);
  return 0;
}

}  // namespace

Registered register_tools(CLI::App& app) {
  auto o = std::make_shared<ToolsOpts>();
  CLI::App* sub = app.add_subcommand(
      "tools", "tool libraries: import a shop's tool table (LinuxCNC, FreeCAD, Fusion 360), export a LinuxCNC one");
  sub->require_subcommand(1);
  CLI::App* imp =
      sub->add_subcommand("import", "a tool table of another system as a millnet tool library (tools.json)");
  imp->add_option("file", o->file, "the table: LinuxCNC tool.tbl, FreeCAD .fctb bit or .fctl library, Fusion 360 .json")
      ->required();
  imp->add_option("--format", o->import_format, "the system that wrote it")
      ->check(CLI::IsMember({"linuxcnc", "freecad", "fusion"}))
      ->required();
  imp->add_option("--units", o->units, "a LinuxCNC table's units: the machine's (default mm)")
      ->check(CLI::IsMember({"mm", "inch"}));
  imp->add_option("--out", o->out_library, "the tool library to write (name it in /cutting/tools_file)")
      ->check(output_file())
      ->required();
  add_common(imp, o->import_common, false);
  CLI::App* exp = sub->add_subcommand(
      "export", "the config's tool library (built-in + /cutting/tools_file) as a LinuxCNC tool table (tool.tbl)");
  exp->add_option("--format", o->export_format, "the table's format")->check(CLI::IsMember({"linuxcnc"}))->required();
  exp->add_option("--out", o->out_table, "the tool table to write")->check(output_file())->required();
  add_common(exp, o->export_common);
  return {sub, [o, imp]() { return imp->parsed() ? run_import(*o) : run_export(*o); }};
}

}  // namespace millnet::app
