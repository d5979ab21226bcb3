#pragma once
// `millnet run`'s summary: what each test part's prediction, roughing and finishing gave, rendered
// as summary.md and the summary page (summary.html). Plain values in: the command gathers them,
// this renders them (and counts what the headline says).
#include "millnet/report/preview.hpp"

#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace millnet::report {

/// One test part of the run.
struct RunPart {
  std::string name;
  int expected = 0;  ///< the family's strategy (generated parts), 0 = unknown

  bool predicted = false;  ///< the network ranked it
  std::string predict_error;
  int top = 0;           ///< the network's top slot
  std::string top_name;  ///< its strategy's name
  double confidence = 0, consistency = 0;
  bool unfamiliar = false;

  bool roughed = false;  ///< a roughing stage ran for it (ok or not)
  bool rough_ok = false;
  std::string rough_error;
  double rough_time_min = 0, retractions = 0, cut_length_mm = 0;
  std::size_t levels = 0;

  bool finished = false;  ///< a finishing stage ran for it (ok or not)
  bool finish_ok = false;
  std::string finish_error;
  std::vector<int> slots;            ///< the strategies simulated, ascending
  std::vector<int> network_rank;     ///< per slot, 1-based; empty without a prediction
  std::vector<int> simulated_rank;   ///< per slot, 1-based, by the aim
  std::vector<double> ra_median_um;  ///< per slot
  std::vector<double> time_min;      ///< per slot, kinematic
  std::vector<double> regret;        ///< per slot: time / the simulated best's − 1 (NaN: unmeasured)
  std::vector<double> spec_share;    ///< per slot: share of the surface in spec (NaN: none)
  std::vector<int> meets_spec;       ///< per slot, 1 / 0
  double spearman = std::numeric_limits<double>::quiet_NaN();

  bool chained = false;  ///< roughing + the top strategy machined on one z-map
  double chain_finisher_depth_of_cut_mm = 0, chain_ra_median_um = 0, chain_uncut_mm2 = 0, chain_rest_mm2 = 0,
         chain_gouge_mm = 0, chain_scallop_max_mm = 0;

  bool jobbed = false;  ///< the part's job was attempted (/run/job)
  bool job_ok = false;  ///< written, and its simulation from the block leaves no gouge
  std::string job_error;
  std::string job_program;  ///< its file name, in parts/<name>/job/
  int job_strategy = 0;     ///< the finishing strategy's slot
  std::size_t job_operations = 0;
  int job_tool_changes = 0;
  double job_time_min = 0, job_gouge_mm = 0;
};

struct RunSummary {
  std::string config_name;                  ///< the config file's name
  std::string labels_file = "labels.json";  ///< the training labels' file name (/dataset/labels)
  std::size_t vectors = 0, training_parts = 0;
  double alpha = 0;
  std::string loo_mode, alpha_edge;  ///< "part" | "vector"; "none" | "low" | "high"
  double accuracy_part = 0, accuracy_vector = 0;
  std::string finish_settings_note, aim;
  std::vector<RunPart> parts;
  std::vector<std::pair<std::string, double>> timing_s;  ///< stage → seconds
  /// Issue 39: a network trained on simulated scores, judged by the regret of its picks leaving out
  /// each training part, beside always one strategy (the one best on the most training parts).
  bool scores = false;
  std::string criterion;  ///< what α was chosen for: "regret" | "rms"
  std::size_t lopo_parts = 0, lopo_misses = 0;
  double lopo_top1 = 0, lopo_mean = 0, lopo_median = 0, lopo_p90 = 0;
  int baseline_slot = 0;  ///< 1-based
  double baseline_top1 = 0, baseline_mean = 0, baseline_median = 0, baseline_p90 = 0;
};

/// What the headline counts.
struct RunCounts {
  std::size_t correct = 0, labelled = 0, failures = 0;
  double mean_spearman = std::numeric_limits<double>::quiet_NaN();
  std::size_t spearman_parts = 0;
  /// Parts finished with a prediction: where the pick is the simulated best, where the pick meets
  /// the specification, and the mean regret of the pick over those where it is measured.
  std::size_t pick_parts = 0, pick_is_best = 0, pick_meets_spec = 0, regret_parts = 0;
  double mean_pick_regret = std::numeric_limits<double>::quiet_NaN();
};
[[nodiscard]] RunCounts run_counts(const RunSummary& s);

/// The regret of the network's pick (its top slot) on a finished part: the simulated regret of
/// that slot (NaN when it was not simulated, no prediction, or nothing met the specification).
[[nodiscard]] double pick_regret(const RunPart& p);

/// summary.md.
[[nodiscard]] std::string run_summary_md(const RunSummary& s);

/// summary.html's content: the table, each part's 3D pages and the charts.
[[nodiscard]] SummaryPage run_summary_page(const RunSummary& s);

/// Slots best first from a 1-based rank per slot ("3 > 1 > 2").
[[nodiscard]] std::string ranking_text(const std::vector<int>& slots, const std::vector<int>& rank);

}  // namespace millnet::report
