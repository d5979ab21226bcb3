#pragma once
// `millnet rough` between the config and the rough module: config → rough::Params, and the files a
// roughed part is written to. The algorithm is rough/ (millnet/rough/rough.hpp).
#include "pocket_job.hpp"

#include "millnet/rough/rough.hpp"

#include <filesystem>
#include <string>

namespace millnet::app {

/// Writes <stem>.nc, <stem>.metrics.json and <stem>.level_<k>.png (k = 1 = top level) into dir.
/// Returns the metrics JSON.
Json write_rough_outputs(const std::filesystem::path& dir, const std::string& stem, const rough::Result& r,
                         const rough::Params& params);

/// rough::Params from a checked config (rough + pocket sections) and the pocket flags.
[[nodiscard]] rough::Params rough_params(const Json& config, const Json& explicit_pocket, const PocketFlags& flags);

}  // namespace millnet::app
