#pragma once
// A test part's job (what `millnet job` writes: one program, the per-operation programs, the tool
// table, job.json and the setup sheet), written by `millnet run` from what the run already computed
// for the part: its prepared mesh, its roughing and its five strategies finished and simulated.
#include "finish_job.hpp"
#include "text.hpp"

#include "millnet/job/operations.hpp"
#include "millnet/rough/rough.hpp"

#include <filesystem>
#include <string>

namespace millnet::app {

/// What the run computed for a part, with the run's settings (the job's, since it reads the same
/// config): the prepared part (named as the run names it), its strategies finished and simulated
/// into `strategies_dir` (finish_part), and its roughing with the configured tool.
struct RunJobInput {
  const job::Part* part = nullptr;
  const PartFinish* finished = nullptr;
  std::filesystem::path strategies_dir;
  const rough::Result* rough = nullptr;  ///< null: the job roughs the part itself
};

/// What the run reports of the job.
struct RunJobResult {
  std::filesystem::path program;  ///< DIR/<name>.job.nc
  int strategy = 0;               ///< the finishing strategy's slot (the simulated ranking's first)
  std::size_t operations = 0;
  int tool_changes = 0;
  double cycle_time_min = 0;  ///< kinematic times + tool changes
  double max_gouge_mm = 0;
  bool gouged = false;
};

/// Writes the part's job into `out` as `millnet job --mesh FILE --config CONFIG_FILE --out OUT`
/// would (the simulated ranking's first strategy), reusing `in`. Throws millnet::Error where that
/// command refuses (a tool that cannot reach, a cut beyond the flutes, a gouging strategy).
RunJobResult write_run_job(const Json& config, const std::string& config_file, const std::string& mesh_file,
                           const RunJobInput& in, const std::filesystem::path& out);

}  // namespace millnet::app
