#pragma once
// Shared pieces of the millnet subcommands: the common options every command has (--quiet,
// --threads N, --config FILE), and the registry main() dispatches through.
#include "config.hpp"

#include "millnet/core/budget.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/job/part.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

struct Common {
  bool quiet = false;
  int threads = -1;                                          ///< -1 = from config (0 = all cores)
  std::string config;                                        ///< empty = defaults
  std::optional<double> max_work, max_memory_mb, max_pairs;  ///< override /limits (issue 12)
  bool no_preview = false;                                   ///< --no-preview: no <stem>.html pages (/report/preview)
};

/// --units and --up, shared by every command that reads meshes (sample, predict, rough, finish,
/// simulate): the accepted values are listed once here and parsed once in prepare().
struct MeshFlags {
  std::optional<std::string> units, up;
  std::optional<std::string> body;  ///< --body NAME|N: one body of a STEP/IGES assembly (/mesh/cad_body)
  void add_to(CLI::App* sub, const std::string& what = "mesh files");
  /// The preparation: the flags, else the config section's "units"/"up" (mm, +z without a section),
  /// and the CAD tessellation of /mesh (config; defaults without one), --body winning over /mesh/cad_body.
  /// Units are explicit (they override a CAD file's own unit) when --units is given or the section's
  /// units differ from the default "mm".
  [[nodiscard]] ingest::PrepareOptions prepare(const Json* section, const Json* config = nullptr) const;
};

/// /mesh of a checked config: chord_tolerance_mm, angular_deflection_rad, cad_body.
[[nodiscard]] ingest::CadOptions cad_options(const Json& config);

/// ingest::load_prepared into a job::Part (named after the file's stem) with what reading a CAD
/// file found; the CAD units note (a --units that contradicts a STEP/IGES file's own unit) is
/// printed once per file on stderr.
[[nodiscard]] job::Part load_part(const std::filesystem::path& file, const ingest::PrepareOptions& prep);

/// The "cad" object of a part's metrics — {format, file_unit, file_unit_mm, units_overridden,
/// chord_tolerance_mm, angular_deflection_rad, body, bodies, faces, triangles} — for a part read
/// from a CAD file; null for mesh files.
[[nodiscard]] Json cad_metrics(const job::Part& part);

/// Command-line overrides of the pocket section (flags win over the config, which wins over the
/// pocket file's own keys).
struct PocketFlags {
  std::optional<double> tool_diameter, stepover, depth, step_down, safe_z, stock_to_leave;
  bool contour = false;
  bool no_contour = false;  ///< --no-contour: leave the wall pass out (/pocket/contour false)
  std::optional<std::string> planner, partition, angle, entry;
  std::optional<std::string> tool_id, material;  ///< --tool ID (library), --material ID
  std::optional<std::string> post;               ///< --post DIALECT (/machine/post)
  void add_to(CLI::App* sub, bool with_planner_flags = true, bool with_depth = true);
};

/// A flag's check against the schema's range for `pointer` (e.g. "/pocket/tool_diameter"): a finite
/// number within minimum / exclusiveMinimum / maximum / exclusiveMaximum, so that a flag and its config key accept the
/// same values (issue 15: NaN passed CLI11's PositiveNumber, 1e308 passed everything).
/// The usage error reads "--tool-diameter: expected a finite number > 0 and ≤ 1000 (/pocket/tool_diameter), got nan".
[[nodiscard]] CLI::Validator schema_range(const std::string& pointer);

/// --out (and every other output path flag): refuses an empty or blank path, which would write
/// into the current folder. The error reads "--out: expected a folder to write into, got an empty path".
[[nodiscard]] CLI::Validator output_path();

/// --post NAME: the controller dialect of every program a command writes (/machine/post; the
/// names of gcode::dialects()).
void add_post_flag(CLI::App* sub, std::optional<std::string>& post);

/// Adds --quiet, --threads, --max-work, --max-memory-mb and (when with_config) --config to a subcommand.
void add_common(CLI::App* sub, Common& common, bool with_config = true);

/// Loads the config named by --config (or the defaults), applies --quiet and --threads
/// (OpenMP thread count; 0 = all cores) and the work limits (/limits, --max-work, --max-memory-mb).
/// Returns the checked config.
[[nodiscard]] Json setup(const Common& common);

/// The work limits setup() settled (the defaults before it ran), handed to every module whose cost
/// is size × resolution.
[[nodiscard]] const WorkLimits& work_limits();

/// Runs a command body: returns 0, or 1 after printing "millnet <cmd>: error: <what>" for a millnet::Error.
using Command = std::function<int()>;

/// Each subcommand registers itself and returns the body main() runs when it was chosen.
struct Registered {
  CLI::App* sub;
  Command body;
};
Registered register_sample(CLI::App& app);
Registered register_dataset(CLI::App& app);
Registered register_train(CLI::App& app);
Registered register_predict(CLI::App& app);
Registered register_pocket(CLI::App& app);
Registered register_compare(CLI::App& app);
Registered register_rough(CLI::App& app);
Registered register_run(CLI::App& app);
Registered register_finish(CLI::App& app);
Registered register_simulate(CLI::App& app);
Registered register_view(CLI::App& app);
Registered register_tools(CLI::App& app);
Registered register_job(CLI::App& app);

/// Messages for the user on stderr (suppressed by --quiet, except errors and warnings).
void info(const std::string& msg);
void warn(const std::string& msg);

/// Expands files and folders (folders: their mesh files, sorted by name) into a list of files.
[[nodiscard]] std::vector<std::filesystem::path> expand_inputs(const std::vector<std::string>& items,
                                                               const std::vector<std::string>& extensions);

}  // namespace millnet::app
