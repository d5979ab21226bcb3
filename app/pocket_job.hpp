#pragma once
// What `pocket`, `compare`, `rough` and `run` share: cut parameters from config + pocket file +
// flags, the planner choice, and the files a planned pocket is written to.
#include "config.hpp"

#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/planner_som.hpp"
#include "millnet/pocket/planner_zigzag.hpp"
#include "millnet/pocket/io/pocket_io.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace millnet::app {

/// Command-line overrides of the pocket section (flags win over the config, which wins over the
/// pocket file's own keys).
struct PocketFlags {
  std::optional<double> tool_diameter, stepover, depth, step_down, safe_z, stock_to_leave;
  bool contour = false;
  std::optional<std::string> planner, partition, angle, entry;
  void add_to(CLI::App* sub, bool with_planner_flags = true, bool with_depth = true);
};

/// `explicit_pocket` = the "pocket" object as written in the config file (no defaults), so that a
/// pocket file's own keys are overridden only by keys the user actually wrote.
[[nodiscard]] pocket::CutParams cut_params(const Json& config, const Json& explicit_pocket,
                                           const pocket::PocketFile* file, const PocketFlags& flags);

/// The pocket section as written in the config file named by --config (empty object otherwise).
[[nodiscard]] Json explicit_pocket_section(const std::string& config_path);

struct PlannerChoice {
  std::string name = "som";           ///< "som" | "zigzag"
  pocket::GridFrame frame;
  pocket::SomParams som;
  pocket::SmoothingParams smooth;
  pocket::ZigzagParams zigzag;
  pocket::Entry entry = pocket::Entry::Predrill;
  bool contour = false;
};
[[nodiscard]] PlannerChoice planner_choice(const Json& config, const pocket::CutParams& cut, const PocketFlags& flags);

/// The typed planner spec of a choice (throws millnet::Error on an unknown planner name).
[[nodiscard]] pocket::PlannerSpec planner_spec(const PlannerChoice& choice);

[[nodiscard]] pocket::PlanResult plan_region(const pocket::Region& region, const pocket::CutParams& cut,
                                             const PlannerChoice& choice);

/// Everything `millnet pocket` writes for one planned pocket: <stem>.nc (only when there is a path),
/// <stem>.metrics.json, <stem>.points.csv, <stem>.png, <stem>.feed.csv, <stem>.feed.png.
void write_pocket_outputs(const std::filesystem::path& dir, const std::string& stem, const pocket::Region& region,
                          const pocket::CutParams& cut, const PlannerChoice& choice, const pocket::PlanResult& plan,
                          const pocket::MachiningResult& m, const std::vector<std::string>& notes);

/// The metrics JSON object (ordered keys as Metrics::to_key_values, then status, planner, parameters).
[[nodiscard]] Json metrics_json(const pocket::PlanResult& plan, const pocket::MachiningResult& m,
                                const pocket::CutParams& cut, const PlannerChoice& choice);

[[nodiscard]] Json cut_json(const pocket::CutParams& cut);

}  // namespace millnet::app
