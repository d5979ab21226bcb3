#pragma once
// What `pocket`, `compare`, `rough` and `run` share: planning a region with the planner choice (its
// settings in settings.hpp), and the files a planned pocket is written to.
#include "settings.hpp"

#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace millnet::app {

[[nodiscard]] pocket::PlanResult plan_region(const pocket::Region& region, const pocket::CutParams& cut,
                                             const PlannerChoice& choice);

/// Everything `millnet pocket` writes for one planned pocket: <stem>.nc (only when there is a path),
/// <stem>.metrics.json, <stem>.points.csv, <stem>.png, <stem>.feed.csv, <stem>.feed.png.
void write_pocket_outputs(const std::filesystem::path& dir, const std::string& stem, const pocket::Region& region,
                          const pocket::CutParams& cut, const PlannerChoice& choice, const pocket::PlanResult& plan,
                          const pocket::MachiningResult& m, const std::vector<std::string>& notes,
                          const gcode::Dialect& post, const Json& cutting_data = Json());

/// The metrics JSON object (ordered keys as Metrics::to_key_values, then status, planner, parameters).
[[nodiscard]] Json metrics_json(const pocket::PlanResult& plan, const pocket::MachiningResult& m,
                                const pocket::CutParams& cut, const PlannerChoice& choice);

[[nodiscard]] Json cut_json(const pocket::CutParams& cut);

/// Empty when a planned pocket is cleared (at most pocket::kClearedUncutMm2 of its reachable area
/// uncut) or did not plan; else what it leaves, for a warning line and the metrics' "warning" (with
/// "cleared": false). Issue 42 §8: adaptive at stepover 0.05 left 11 % uncut with status ok, silently.
[[nodiscard]] std::string uncut_warning(const pocket::PlanResult& plan, const pocket::MachiningResult& m);

}  // namespace millnet::app
