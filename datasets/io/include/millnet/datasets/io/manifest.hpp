#pragma once
// The model-vector table on disk: <dir>/vectors.csv (datasets::table_csv / read_table) and its
// manifest, <dir>/manifest.json (target millnet::datasets_io; nlohmann lives in its one .cpp). This
// adapter is the one owner of the manifest: it writes it and reads it back.
//
//   {"format": "millnet-vectors", "format_version": 1, "program": "millnet", "program_version",
//    "csv": "vectors.csv", "csv_fnv1a64", "csv_bytes", "grid", "inputs" (grid²), "outputs" (8),
//    "aspect_column", "counts": {"rows", "parts", "rows_per_label": {"<label>": rows}},
//    "strategies": [8 names], "hash": "fnv1a64",
//    "input_files": [{"name", "file", "label", "fnv1a64", "bytes", "triangles", "degenerate_triangles"}],
//    "config": the recipe echo (datasets::recipe_json) or null,
//    "labelling" (optional): the simulated labels and their figures (app: build_dataset)}
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/table.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::datasets_io {

inline constexpr int kManifestFormatVersion = 1;

/// A part file echoed in the manifest.
struct ManifestFile {
  std::string name, file;
  int label = 0;
  std::string fnv1a64;  ///< hex, as datasets::to_hex
  std::uintmax_t bytes = 0;
  std::size_t triangles = 0;
  std::size_t degenerate_triangles = 0;
  bool operator==(const ManifestFile&) const = default;
};

/// What a manifest says.
struct Manifest {
  std::string program_version;
  std::string csv_fnv1a64;  ///< hex hash of vectors.csv
  std::size_t csv_bytes = 0;
  int grid = 0;  ///< n; inputs = n²
  bool aspect_column = false;
  bool wall_share_column = false;  ///< "wall_share_column" (written only when true)
  std::size_t rows = 0, parts = 0;
  std::map<int, std::size_t> rows_per_label;
  std::vector<std::string> strategies;  ///< the table's strategy names
  std::vector<ManifestFile> input_files;
  /// "config" as JSON text: the recipe echo as written ("null" when the table has none); after
  /// read_manifest the same value, compactly re-serialized (compare it as JSON, not as text).
  std::string config_json = "null";
  std::optional<double> raster_mm;  ///< config.raster_mm, the recipe's sampling raster
  /// "labelling" as JSON text (parts labelled by virtual machining, every strategy's figures, the
  /// agreement with the recipe's labels); empty ⇒ the key is absent. Re-serialized on read.
  std::string labelling_json;
  bool operator==(const Manifest&) const = default;
};

/// The manifest of `table`, whose CSV text (datasets::table_csv) is `csv`. Throws millnet::Error
/// when table.config_json is not valid JSON. O(rows + csv bytes).
[[nodiscard]] Manifest manifest_of(const datasets::Table& table, std::string_view csv);

/// The manifest's bytes: the layout above, two-space indent, one input file a line, config_json as
/// it is.
[[nodiscard]] std::string manifest_text(const Manifest& manifest);

/// Writes <dir>/vectors.csv then <dir>/manifest.json, each atomically (temporary file + rename; a
/// failure leaves no partial file: a manifest never describes a CSV that is not there). Creates dir.
/// Throws millnet::Error (inconsistent rows: see datasets::table_csv). O(rows · n²).
void write_table(const datasets::Table& table, const std::filesystem::path& dir);

/// vectors.csv written row by row, then its manifest: the bytes of write_table for the same rows,
/// with one row in memory at a time (rank 0 of `mpirun … millnet dataset` streams a library's table
/// to disk as the rows come in, issue 10). The CSV goes to a temporary file (core/atomic_file.hpp)
/// that becomes vectors.csv in finish() (staged in the open OutputSet, if any), then the manifest;
/// a writer destroyed before finish() leaves nothing. Memory: O(parts) (the part names counted).
class TableWriter {
public:
  /// Creates `dir` and opens the CSV with its header. Throws millnet::Error.
  TableWriter(const std::filesystem::path& dir, int grid_n, bool has_aspect, datasets::StrategyNames strategies,
              bool has_wall_share = false);
  TableWriter(const TableWriter&) = delete;
  TableWriter& operator=(const TableWriter&) = delete;
  ~TableWriter();
  /// Appends one row. The rows of one source must be consecutive and their ids distinct (as
  /// build_table makes them); throws millnet::Error otherwise or as datasets::append_csv_row. O(n²).
  void add(const datasets::Row& row);
  /// Writes <dir>/vectors.csv then <dir>/manifest.json (config and labelling echoed as in Table).
  void finish(const std::vector<datasets::SourceFile>& sources, const std::string& config_json,
              const std::string& labelling_json);
  [[nodiscard]] std::size_t rows() const { return rows_; }

private:
  struct Impl;
  std::filesystem::path dir_;
  int grid_n_;
  bool has_aspect_;
  bool has_wall_share_ = false;
  datasets::StrategyNames strategies_;
  std::unique_ptr<Impl> impl_;
  std::size_t rows_ = 0;
};

/// Reads <path>. Throws millnet::Error "<file>: <key>: what" when it cannot be read or parsed, a key
/// is missing or has the wrong type, "format" is not "millnet-vectors" or "format_version" is not 1.
[[nodiscard]] Manifest read_manifest(const std::filesystem::path& path);

/// True when `dir` holds vectors.csv and a manifest.json built from `recipe` (same recipe echo,
/// compared as JSON) over part files with the same bytes (FNV-1a 64). An unreadable manifest
/// counts as out of date. O(part file bytes).
[[nodiscard]] bool table_up_to_date(const std::filesystem::path& dir, const datasets::Recipe& recipe);

}  // namespace millnet::datasets_io
