#pragma once
// The learning pipeline's steps as functions, shared by `dataset`, `train`, `predict` and `run`.
#include "settings.hpp"

#include "millnet/classifier/network.hpp"
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/features.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/job/part.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

/// Builds the table of `recipe` into out_dir (vectors.csv + manifest.json). When `reuse` and
/// out_dir already holds a table built from the same recipe and the same part-file bytes, nothing is
/// rebuilt. Parts labelled "simulate" get the strategy their virtual machining ranks first
/// (settings from the config's /finish and /simulate; every strategy's figures in the manifest under
/// "labelling"; no program or picture is written for a label). With
/// `with_agreement`, every part is simulated and out_dir/agreement.md tells how often the
/// simulated best agrees with the recipe's label. Returns true when the table was (re)built.
bool build_dataset(datasets::Recipe recipe, const std::filesystem::path& out_dir, bool reuse, const Json& config,
                   bool with_agreement = false);

/// Figures of a training run (also written to DIR/train_report.json).
struct TrainSummary {
  double alpha = 0;
  std::string mode, edge;
  double rms_part = 0, rms_vector = 0, accuracy_part = 0, accuracy_vector = 0;
  std::size_t vectors = 0, parts = 0;
  /// Issue 39: the parts' picks judged by their regret (leave-one-part-out at α), and the shop's
  /// baseline of always one strategy. Meaningful when the outputs are simulated scores.
  std::string criterion = "rms";
  bool scores = false;  ///< some output row is not one-hot (labels by simulation)
  classifier::RegretSummary regret;
  classifier::Baseline baseline;
};

/// Trains on a vectors.csv and writes model.json (with its "features"), sampling.json (the same
/// raster and grid, for older readers), loo_curve.csv/.png,
/// verification.csv/.png and train_report.json into out_dir.
TrainSummary train_model(const std::filesystem::path& dataset_csv, const Json& config,
                         const std::filesystem::path& out_dir);

/// One part's prediction.
struct PartPrediction {
  std::string name, file;
  bool ok = false;
  std::string error;
  int top = 0;  ///< 1-based strategy slot
  /// P(top is the part's best): the model's calibration (leave-one-part-out, falling towards the
  /// top's prior as the part gets unfamiliar); the mean output of the top for model files without one.
  double confidence = 0;
  double regret_risk = 0;               ///< expected regret of the top (the network's average over its neighbours)
  std::vector<double> expected_regret;  ///< K, per strategy
  double consistency = 0;               ///< share of variants whose top strategy is the overall top
  bool unfamiliar = false;
  double d2_min = 0;                ///< smallest over the variants
  int expected = 0;                 ///< label given for a test part (0 = unknown)
  std::vector<double> mean;         ///< K mean probabilities
  std::vector<double> totals;       ///< K sums over the variants (the paper's Fig. 8 totals)
  std::vector<double> first_share;  ///< K share of variants ranking each strategy first
  std::vector<std::string> strategies;
  std::filesystem::path png;
};

struct PredictInput {
  std::filesystem::path file;
  std::string name;  ///< empty ⇒ file stem
  int expected = 0;
  std::shared_ptr<const job::Part> part;  ///< the part when already loaded; null ⇒ read from file
};

/// A trained model folder, read once: model.json (the classifier and, under "features", its inputs'
/// raster and grid; sampling.json instead for folders written before that key), with the
/// prediction's augmentation from the config (/predict/augment).
struct ModelFolder {
  std::filesystem::path dir;
  classifier::Model model;
  datasets::FeatureSpec spec;
};
[[nodiscard]] ModelFolder load_model_folder(const std::filesystem::path& dir, const Json& config);

/// Predicts every part (a broken part is reported in its entry and the batch goes on) and writes
/// predictions.json, predictions.csv and one PNG per part into out_dir.
std::vector<PartPrediction> predict_parts(const ModelFolder& model, const std::vector<PredictInput>& parts,
                                          const ingest::PrepareOptions& prep, const std::filesystem::path& out_dir);

}  // namespace millnet::app
