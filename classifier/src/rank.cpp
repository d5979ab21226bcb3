#include "millnet/classifier/rank.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>

namespace millnet::classifier {

Ranking rank(const Prediction& pr) {
  const auto rows = static_cast<std::size_t>(pr.probabilities.rows());
  const auto K = static_cast<std::size_t>(pr.probabilities.cols());
  if (rows == 0) throw Error("rank: the prediction has no variant rows");
  const auto M = static_cast<double>(rows);
  Ranking r;
  r.mean.assign(K, 0.0);
  r.totals.assign(K, 0.0);
  r.first_share.assign(K, 0.0);
  r.variant_top.reserve(rows);
  for (std::size_t v = 0; v < rows; ++v) {
    const auto row = pr.probabilities.row(static_cast<Eigen::Index>(v));
    Eigen::Index best = 0;
    row.maxCoeff(&best);
    r.variant_top.push_back(static_cast<int>(best) + 1);
    r.first_share[static_cast<std::size_t>(best)] += 1.0 / M;
    for (std::size_t k = 0; k < K; ++k) r.totals[k] += row(static_cast<Eigen::Index>(k));
    r.unfamiliar_variants += pr.unfamiliar[v] ? 1U : 0U;
  }
  for (std::size_t k = 0; k < K; ++k) r.mean[k] = r.totals[k] / M;
  r.top = static_cast<int>(std::max_element(r.mean.begin(), r.mean.end()) - r.mean.begin()) + 1;
  r.confidence = r.mean[static_cast<std::size_t>(r.top - 1)];
  r.consistency = static_cast<double>(std::count(r.variant_top.begin(), r.variant_top.end(), r.top)) / M;
  r.d2_min = pr.d2_min.minCoeff();
  r.unfamiliar = 2 * r.unfamiliar_variants > rows;  // most variants far from every stored model
  r.order.resize(K);
  for (std::size_t k = 0; k < K; ++k) r.order[k] = k;
  std::stable_sort(r.order.begin(), r.order.end(), [&](std::size_t a, std::size_t b) { return r.mean[a] > r.mean[b]; });
  return r;
}

std::vector<int> slot_ranks(const std::vector<double>& totals, const std::vector<int>& slots) {
  std::vector<std::size_t> idx(slots.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  auto total = [&](std::size_t i) {
    const auto k = static_cast<std::size_t>(slots[i] - 1);
    return k < totals.size() ? totals[k] : 0.0;
  };
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return total(a) > total(b); });
  std::vector<int> rank(slots.size());
  for (std::size_t r = 0; r < idx.size(); ++r) rank[idx[r]] = static_cast<int>(r + 1);
  return rank;
}

}  // namespace millnet::classifier
