// The training's curves (train_curves.hpp).
#include "train_curves.hpp"

#include "report_util.hpp"
#include "text.hpp"

#include "millnet/classifier/rank.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/report/plots.hpp"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace millnet::app {
namespace fs = std::filesystem;

/// loo_curve.csv (alpha, the chosen mode's rms, both modes' figures) and loo_curve.png.
void write_loo_curve(const classifier::Model& model, const fs::path& out_dir) {
  const classifier::LooReport& loo = model.loo;
  std::ostringstream curve;
  // mean_regret (issue 39): the leave-one-part-out regret of the parts' picks, with the regret criterion.
  const bool regret = !model.regret_curve.empty() && model.regret_curve.size() >= loo.curve.size();
  curve << "alpha,rms,rms_part,rms_vector,accuracy_part,accuracy_vector" << (regret ? ",mean_regret" : "") << "\n";
  std::vector<double> xs, part_rms, vec_rms, regrets;
  const bool part_mode = loo.mode == classifier::LooMode::PartOut;
  for (std::size_t i = 0; i < loo.curve.size(); ++i) {  // O(scan points)
    const classifier::CurvePoint& c = loo.curve[i];
    curve << format_double(c.alpha) << "," << format_double(part_mode ? c.rms_part : c.rms_vector) << ","
          << format_double(c.rms_part) << "," << format_double(c.rms_vector) << "," << format_double(c.accuracy_part)
          << "," << format_double(c.accuracy_vector);
    if (regret) {
      curve << "," << format_double(model.regret_curve[i].second);
      regrets.push_back(100 * model.regret_curve[i].second);
    }
    curve << "\n";
    xs.push_back(c.alpha);
    part_rms.push_back(c.rms_part);
    vec_rms.push_back(c.rms_vector);
  }
  write_file_atomic(out_dir / "loo_curve.csv", curve.str());
  if (xs.empty()) {  // /train/fixed_alpha: no scan, the one point at the given α (the chart failed on "no points")
    xs = {model.alpha};
    part_rms = {loo.rms_part_at_alpha};
    vec_rms = {loo.rms_vector_at_alpha};
  }
  report::LinePlotOptions lo;
  lo.log_x = true;
  lo.show_points = true;
  lo.marker = report::Marker{
      model.alpha, "chosen alpha = " + fixed(model.alpha, 3) + " (" + classifier::to_string(loo.mode) + " LOO)"};
  (void)report::line_plot_png(out_dir / "loo_curve.png",
                              {{"leave-one-part-out", xs, part_rms}, {"leave-one-vector-out (paper)", xs, vec_rms}},
                              "Leave-one-out RMS error against the penalty coefficient alpha", "alpha (log scale)",
                              "RMS error of the outputs", lo);
  if (regret && !xs.empty())
    (void)report::line_plot_png(out_dir / "loo_regret.png", {{"leave-one-part-out mean regret", xs, regrets}},
                                "Mean regret of the parts' picks against the penalty coefficient alpha",
                                "alpha (log scale)", "mean regret, % (time of the pick / best time - 1)", lo);
}

/// verification.csv and .png: filtration (self included) and verification (the chosen mode's
/// exclusion) of every stored vector, the paper's Fig. 6. O(vectors · strategies).
void write_verification(const datasets::Table& table, const classifier::LooReport& loo, const fs::path& out_dir) {
  const bool part_mode = loo.mode == classifier::LooMode::PartOut;
  std::ostringstream ver;
  ver << "id,source";
  const auto K = loo.filtration.cols();
  for (Eigen::Index k = 1; k <= K; ++k) ver << ",filtration_" << k;
  for (Eigen::Index k = 1; k <= K; ++k) ver << ",verification_" << k;
  ver << "\n";
  std::vector<int> labels;
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    ver << table.rows[i].id << "," << table.rows[i].source;
    for (Eigen::Index k = 0; k < K; ++k) ver << "," << format_double(loo.filtration(r, k));
    for (Eigen::Index k = 0; k < K; ++k) ver << "," << format_double(loo.verification(r, k));
    ver << "\n";
    labels.push_back(table.rows[i].label);
  }
  write_file_atomic(out_dir / "verification.csv", ver.str());
  const classifier::TrueOutputs t = classifier::true_label_outputs(loo, labels);
  if (!t.filtration.empty())
    (void)report::multi_line_png(
        out_dir / "verification.png",
        {{"filtration (self included)", t.filtration},
         {std::string("verification (") + (part_mode ? "part" : "vector") + " left out)", t.verification}},
        "Output of the true strategy for every stored vector (paper Fig. 6)", "stored vector",
        "output of the labelled strategy");
}

}  // namespace millnet::app
