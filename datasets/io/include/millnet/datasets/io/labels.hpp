#pragma once
// Labels by virtual machining as a cache (issue 39 §2): <recipe folder>/labels.json holds, per
// part, the hash of its file and every strategy's simulated figures under the settings they were
// computed with, so that a table is built without simulating a part whose file and settings are
// unchanged. A label is a deterministic computation: `millnet dataset --relabel` recomputes every
// one, and the same part and settings give the same bytes.
//
//   {"format": "millnet-labels", "format_version": 1, "aim": "time_to_spec",
//    "settings": {…everything a label depends on: /finish, /simulate, /cutting, /machine…},
//    "parts": [{"name", "fnv1a64", "bytes", "best",
//               "strategies": [{"strategy", "rank", "score", "time_kinematic_min", "spec_share",
//                               "meets_spec", "max_gouge_mm", "ra_median_um", "ra_p90_um",
//                               "uncut_area_mm2", "regret"}]}]}
//
// "score" is simulate::aim_scores' (the best 1, a strategy twice as long 0.5, one that gouges or
// misses the specification 0): the outputs of the part's model vectors. NaN is written as null.
#include "millnet/datasets/table.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace millnet::datasets_io {

inline constexpr int kLabelsFormatVersion = 1;

struct StrategyLabel {
  int strategy = 0;  ///< slot 1..8
  int rank = 0;      ///< 1-based under the aim
  double score = 0;  ///< simulate::aim_scores
  double time_min = 0, spec_share = 0, max_gouge_mm = 0, ra_median_um = 0, ra_p90_um = 0, uncut_area_mm2 = 0;
  double regret = 0;  ///< NaN when unmeasured
  bool meets_spec = false;
};

struct PartLabel {
  std::string name;
  std::string fnv1a64;  ///< of the part file, datasets::to_hex
  std::uintmax_t bytes = 0;
  int best = 0;  ///< the slot ranked first
  std::vector<StrategyLabel> strategies;
  /// The model vector's outputs: each strategy's score in its slot, 0 in slots not simulated. O(strategies).
  [[nodiscard]] std::array<double, datasets::kStrategySlots> outputs() const;
};

struct LabelFile {
  std::string aim;
  std::string settings_json;  ///< compact JSON text of the settings object
  std::vector<PartLabel> parts;
  /// The label of the part named `name` whose file hashes to `fnv1a64` and has `bytes`; null
  /// otherwise. O(parts).
  [[nodiscard]] const PartLabel* find(const std::string& name, const std::string& fnv1a64, std::uintmax_t bytes) const;
};

/// Reads a labels file; every error names the file and the key (parts[3].strategies[1].score: …).
[[nodiscard]] LabelFile read_labels(const std::filesystem::path& path);

/// The file's text: keys sorted, parts in the order given, numbers shortest round-trip. Same
/// labels ⇒ same bytes.
[[nodiscard]] std::string labels_text(const LabelFile& labels);

/// One part's label as compact JSON text and back (a unit's result between MPI ranks; the
/// manifest's echo). parse_part_label's errors name `source`.
[[nodiscard]] std::string part_label_text(const PartLabel& label);
[[nodiscard]] PartLabel parse_part_label(const std::string& text, const std::string& source);

/// Writes labels_text atomically (temporary file + rename).
void write_labels(const std::filesystem::path& path, const LabelFile& labels);

}  // namespace millnet::datasets_io
