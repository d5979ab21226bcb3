#pragma once
// How often the strategy a simulation ranks best agrees with a part's label in the recipe (the
// family labels of the default training set are the paper's; the simulation is ours).
#include <map>
#include <vector>

namespace millnet::datasets {

/// One part: its recipe label (< 1 = none, e.g. labelled by simulation) and the slot ranked best.
struct LabelledBest {
  int recipe_label = 0;
  int simulated_best = 0;
};

/// The parts of one recipe label.
struct LabelAgreement {
  int label = 0;
  int parts = 0;
  int agree = 0;                      ///< parts whose simulated best is the label
  std::map<int, int> simulated_best;  ///< simulated best slot → parts, ascending slot
};

/// Per recipe label ≥ 1, ascending; parts without a recipe label are left out. O(n log n).
[[nodiscard]] std::vector<LabelAgreement> label_agreement(const std::vector<LabelledBest>& parts);

}  // namespace millnet::datasets
