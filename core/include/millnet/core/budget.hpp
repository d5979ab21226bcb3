#pragma once
// Work and memory budgets (issue 12 §1): every stage whose cost is the input's size × a resolution
// (raster cells, tool points, feed-map cells, z-map cells, CL points, N² pairs) estimates its cost
// from the input BEFORE allocating and refuses, with one line, what would not fit:
//
//   stepover 0.001 mm over a 100 × 100 mm pocket makes 1.0e10 tool points (≈ 240 GB); the limit is
//   2.0e7 (--max-work, /limits/max_work)
//
// The estimate functions live in the module that owns the stage (pocket::estimate_work, …); this
// header holds only the typed limits and the one check that formats the refusal.
#include <string>

namespace millnet {

/// The limits a run works under (config /limits, flags --max-work and --max-memory-mb). The defaults
/// fit comfortably in 24 GiB and keep every stage to minutes on two cores.
struct WorkLimits {
  double max_work = 2e7;                               ///< items (points, cells, pairs) per stage
  double max_memory_bytes = 4.0 * 1024 * 1024 * 1024;  ///< bytes one stage may allocate (4 GiB)
  /// Vector pairs of an N² stage (the classifier's leave-one-out distances): 5e9 ≈ 70,000 stored
  /// vectors, about 5 minutes at the 1.6e7 pairs/s measured on two cores (bench_classifier).
  double max_pairs = 5e9;
};

/// A stage's cost, computed from the input before anything is allocated.
struct WorkEstimate {
  std::string cause;  ///< what makes it, naming the parameter: "stepover 0.001 mm over a 100 × 100 mm pocket"
  double count = 0;   ///< how many items (≥ 0; +inf when it overflows)
  std::string unit;   ///< plural noun of the items: "tool points"
  double bytes = 0;   ///< memory the stage holds for them
  /// Checked against the memory limit only: stages whose cost per item is a few bytes of storage and
  /// a constant time (a z-map's cells), where the memory, not the count, is what runs out.
  bool memory_only = false;
  /// Checked against max_pairs instead of max_work: an N² stage whose items are vector pairs.
  bool pairs = false;
};

/// Throws millnet::Error with the one-line refusal when est.count > limits.max_work (unless
/// est.memory_only) or est.bytes > limits.max_memory_bytes (a NaN count or size is refused too). A count equal to the limit passes.
void check_work(const WorkEstimate& est, const WorkLimits& limits);

/// "1.0e10": scientific notation with `decimals` digits after the point (a count in a refusal;
/// check_work adds digits until an estimate and its limit print differently).
[[nodiscard]] std::string format_count(double n, int decimals = 1);
/// A size or resolution in a cause: up to 6 significant digits (12 decimals below 0.001), no
/// exponent from 1e-7 to 1e12 ("0.00001", "100", "1000000", "12.3457").
[[nodiscard]] std::string format_size(double v);
/// "240 GB", "3.1 MB", "512 B": decimal units, two significant digits from 10 up.
[[nodiscard]] std::string format_bytes(double bytes);

}  // namespace millnet
