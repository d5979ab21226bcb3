#include "millnet/datasets/agreement.hpp"

namespace millnet::datasets {

std::vector<LabelAgreement> label_agreement(const std::vector<LabelledBest>& parts) {
  std::map<int, LabelAgreement> per;
  for (const LabelledBest& p : parts) {
    if (p.recipe_label < 1) continue;
    LabelAgreement& a = per[p.recipe_label];
    a.label = p.recipe_label;
    ++a.parts;
    a.agree += p.simulated_best == p.recipe_label ? 1 : 0;
    ++a.simulated_best[p.simulated_best];
  }
  std::vector<LabelAgreement> out;
  out.reserve(per.size());
  for (auto& [label, a] : per) out.push_back(std::move(a));
  return out;
}

}  // namespace millnet::datasets
