#pragma once
// The per-part ranking of a prediction over a part's variants (the paper's Fig. 8 totals):
//   Prediction pr = predict(model, model_vectors);   // one row per rotated/flipped variant
//   Ranking r = rank(pr);                            // r.top, r.confidence, r.consistency, r.unfamiliar
#include "millnet/classifier/network.hpp"

#include <cstddef>
#include <vector>

namespace millnet::classifier {

struct Ranking {
  int top = 0;              ///< 1-based strategy slot with the highest mean probability (first on ties)
  double confidence = 0;    ///< mean probability of the top strategy over the variants
  double consistency = 0;   ///< share of variants whose own top strategy is `top`
  bool unfamiliar = false;  ///< most variants are far from every stored model vector
  std::size_t unfamiliar_variants = 0;
  double d2_min = 0;                ///< smallest over the variants
  std::vector<double> mean;         ///< K mean probabilities
  std::vector<double> totals;       ///< K sums over the variants
  std::vector<double> first_share;  ///< K share of variants ranking each strategy first
  std::vector<int> variant_top;     ///< per variant: its 1-based top slot (first on ties)
  std::vector<std::size_t> order;   ///< 0-based slots by mean probability, descending (stable)
};

/// Aggregates the M variant rows of `pr` (M ≥ 1, K columns). Throws millnet::Error when M = 0. O(M·K + K log K).
[[nodiscard]] Ranking rank(const Prediction& pr);

/// The 1-based rank of each of `slots` (1-based strategy slots, e.g. the strategies a part was
/// finished with) by totals[slot − 1], highest first; ties keep the order of `slots`; a slot beyond
/// totals counts as 0. E.g. totals {0.2, 0.9, 0.5}, slots {1, 2, 3} ⇒ {3, 1, 2}. O(n log n).
[[nodiscard]] std::vector<int> slot_ranks(const std::vector<double>& totals, const std::vector<int>& slots);

}  // namespace millnet::classifier
