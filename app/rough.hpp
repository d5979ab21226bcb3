#pragma once
// `millnet rough`: the files a roughed part is written to (its settings: rough_params in
// settings.hpp). The algorithm is rough/ (millnet/rough/rough.hpp).
#include "pocket_job.hpp"

#include "millnet/rough/rough.hpp"

#include <filesystem>
#include <string>

namespace millnet::app {

/// Writes <stem>.nc, <stem>.metrics.json and <stem>.level_<k>.png (k = 1 = top level) into dir, and
/// the 3D preview <stem>.html (with the prepared part when given; the roughing tool drawn is params.cut.tool).
/// Returns the metrics JSON.
Json write_rough_outputs(const std::filesystem::path& dir, const std::string& stem, const rough::Result& r,
                         const rough::Params& params, const gcode::Dialect& post, const Json& cutting_data = Json(),
                         const ingest::Mesh* part = nullptr, const Json& cad = Json());

}  // namespace millnet::app
