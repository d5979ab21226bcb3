#pragma once
// The model-vector table (Korosec & Kopac §3.5): one row per augmented variant of a part, n×n grid
// heights as inputs (n = 15 in the paper: 225 inputs) and 8 one-hot strategy outputs.
//
// On disk (ARCHITECTURE.md "Formats"): <dir>/vectors.csv + <dir>/manifest.json, written together by
// datasets_io::write_table (millnet/datasets/io/manifest.hpp, the manifest's one owner).
//   CSV header, exactly:  id,source,label,axis,angle,flip,in_1_1,…,in_n_n,out_1,…,out_8[,aspect][,wall_share]
//   * in_<r>_<c>: height in mm above the variant's lowest point at grid row r (r = 1 at min y) and
//     column c (c = 1 at min x), 1-based; the grid spans the footprint rectangle corner to corner.
//   * out_k: 1 for the labelled strategy, 0 elsewhere (all 0 when the label is unknown).
//   * label: 1-based strategy slot, 0 = unknown; axis: x|y|z; angle: degrees; flip: 0|1.
//   * aspect (optional, last): footprint a/b = width along x / width along y of the variant. An
//     extra feature kept apart from the in_* columns; the classifier uses only in_* unless told.
//   * wall_share (optional, last): the part's share of its machined (upward) surface steeper than
//     60° (datasets::wall_share), the same on every variant of the part: what decides whether a
//     raster finish meets the specification, which a 15×15 grid does not see (issue 39 §3; the
//     model learns from it when its features say so, classifier::InputSpec::wall_share_weight).
//   * numbers are written in the shortest text that reads back to the same double (bit for bit);
//     text fields are quoted (RFC 4180) when they contain a comma or a quote.
#include "millnet/augment/variants.hpp"
#include "millnet/datasets/tolerances.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace millnet::datasets {

using StrategyNames = std::array<std::string, kStrategySlots>;

/// The paper's five strategies in slots 1..5, and "spare 6".."spare 8".
[[nodiscard]] StrategyNames default_strategy_names();

/// One model vector.
struct Row {
  std::string id;      ///< unique within the table, e.g. "s1_steep_plateaus_01#7"
  std::string source;  ///< part name the vector came from (leave-one-part-out groups by it)
  int label = 0;       ///< 1..8, 0 = unknown
  augment::Axis axis = augment::Axis::X;
  double angle_deg = 0;
  bool flip = false;
  std::vector<double> inputs;  ///< n·n heights, mm, row-major (row = y): inputs[(r−1)·n + (c−1)]
  std::array<double, kStrategySlots> outputs{};  ///< one-hot over the 8 slots
  double aspect = 0;                             ///< footprint a/b (only meaningful when Table::has_aspect)
  double wall_share = 0;                         ///< the part's wall share (Table::has_wall_share)
};

/// A part file that went into a table (echoed in the manifest with its hash).
struct SourceFile {
  std::string name;
  std::string file;  ///< as given in the recipe
  int label = 0;
  std::uint64_t fnv1a64 = 0;  ///< of the file's bytes
  std::uintmax_t bytes = 0;
  std::size_t triangles = 0;
  std::size_t degenerate_triangles = 0;
};

struct Table {
  int grid_n = 15;              ///< inputs per row = grid_n²
  bool has_aspect = false;      ///< write/read the optional `aspect` column
  bool has_wall_share = false;  ///< write/read the optional `wall_share` column
  StrategyNames strategies = default_strategy_names();
  std::vector<Row> rows;
  // Provenance for the manifest (not in the CSV; empty after read_table).
  std::vector<SourceFile> sources;
  std::string config_json;  ///< JSON text echoed as manifest "config" (must be valid JSON; empty ⇒ null)
  /// JSON text written as manifest "labelling" (every strategy's simulated figures per part, the
  /// agreement with the recipe's labels); empty ⇒ the key is left out.
  std::string labelling_json;

  [[nodiscard]] std::size_t inputs_per_row() const {
    return static_cast<std::size_t>(grid_n) * static_cast<std::size_t>(grid_n);
  }
  /// N×n² inputs (row i = rows[i]), then `wall_share_copies` equal columns of each row's wall share
  /// (the network's inputs of a table with the column: classifier::InputSpec).
  [[nodiscard]] Eigen::MatrixXd inputs_matrix(int wall_share_copies = 0) const;
  /// N×8 outputs.
  [[nodiscard]] Eigen::MatrixXd outputs_matrix() const;
  /// Part name of each row (groups for leave-one-part-out).
  [[nodiscard]] std::vector<std::string> row_sources() const;
};

/// The CSV header's column names for grid n (with `aspect` last when asked).
[[nodiscard]] std::vector<std::string> column_names(int grid_n, bool with_aspect, bool with_wall_share = false);

/// One-hot output for a 1-based label (all zeros for 0). Throws millnet::Error outside 0..8.
[[nodiscard]] std::array<double, kStrategySlots> one_hot(int label);

/// The CSV header line (with its '\n') for grid n.
[[nodiscard]] std::string csv_header(int grid_n, bool with_aspect, bool with_wall_share = false);

/// Appends one row's CSV line (with its '\n'). Throws millnet::Error for the wrong number of
/// inputs, a label outside 0..8 or a text field with a line break (ids are not checked: the caller
/// knows its ids). O(n²).
void append_csv_row(std::string& out, const Row& row, int grid_n, bool with_aspect, bool with_wall_share = false);

/// The CSV text of the table (datasets_io::write_table writes it beside the manifest). Throws
/// millnet::Error for a row with the wrong number of inputs, a label outside 0..8, a duplicate id or
/// a text field with a line break. O(rows · n²).
[[nodiscard]] std::string table_csv(const Table& table);

/// Reads a vectors.csv (the strategy names are the defaults: names live in the manifest). Errors
/// name "<file>:<line>: what", with the column name for a bad value: wrong/missing/unexpected
/// header column, wrong field count, non-number or non-finite value, label outside 0..8, a label
/// that disagrees with the one-hot outputs, axis not x|y|z, flip not 0|1, duplicate id, no rows.
/// O(file size).
[[nodiscard]] Table read_table(const std::filesystem::path& csv_path);

}  // namespace millnet::datasets
