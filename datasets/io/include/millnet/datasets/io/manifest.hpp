#pragma once
// The dataset manifest (<dir>/manifest.json beside vectors.csv) read back (target
// millnet::datasets_io; nlohmann lives in its one .cpp). datasets::write_table writes it; this
// adapter is the one place that reads it, so its keys are known in one place.
#include "millnet/datasets/build.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::datasets_io {

/// A part file echoed in the manifest.
struct ManifestFile {
  std::string name, file;
  int label = 0;
  std::string fnv1a64;  ///< hex, as datasets::to_hex
};

/// What the commands need of a manifest.
struct Manifest {
  std::vector<std::string> strategies;  ///< the table's strategy names (empty when absent)
  std::optional<double> raster_mm;      ///< the sampling raster of the recipe ("config"/"raster_mm")
  std::vector<ManifestFile> input_files;
};

/// Reads <path>. Throws millnet::Error naming the file when it cannot be read or parsed.
[[nodiscard]] Manifest read_manifest(const std::filesystem::path& path);

/// True when `dir` holds vectors.csv and a manifest.json built from `recipe` (same recipe echo,
/// compared as JSON) over part files with the same bytes (FNV-1a 64). An unreadable manifest
/// counts as out of date. O(part file bytes).
[[nodiscard]] bool table_up_to_date(const std::filesystem::path& dir, const datasets::Recipe& recipe);

}  // namespace millnet::datasets_io
