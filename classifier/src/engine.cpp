// The classifier's stored set in the order the kernels like (engine.hpp): validation, the
// permutation that makes equal output rows contiguous, groups and patterns.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "engine.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier::detail {

using Eigen::MatrixXd;

Prepared prepare(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups) {
  const Index n = Xn.rows();
  if (n < 2) throw Error("classifier: need at least 2 stored vectors, got " + std::to_string(n));
  if (Xn.cols() < 1) throw Error("classifier: inputs have no columns (expected N×D, D ≥ 1)");
  if (Y.rows() != n || Y.cols() < 1)
    throw Error("classifier: outputs are " + std::to_string(Y.rows()) + "×" + std::to_string(Y.cols()) + ", expected " +
                std::to_string(n) + "×K with K ≥ 1 (one row per input vector)");
  if (static_cast<Index>(groups.size()) != n)
    throw Error("classifier: " + std::to_string(groups.size()) + " group ids for " + std::to_string(n) +
                " vectors (expected one source part per vector)");
  if (!Xn.allFinite()) throw Error("classifier: inputs contain NaN or infinite values");
  if (!Y.allFinite()) throw Error("classifier: outputs contain NaN or infinite values");
  if (n > std::numeric_limits<std::int32_t>::max()) throw Error("classifier: too many stored vectors");

  Prepared P;
  const auto un = static_cast<std::size_t>(n);
  std::vector<Index> ord(un);
  std::iota(ord.begin(), ord.end(), Index{0});
  // O(N log N · K): lexicographic order of output rows, stable, so equal rows keep input order.
  std::stable_sort(ord.begin(), ord.end(), [&Y](Index a, Index b) {
    for (Index k = 0; k < Y.cols(); ++k)
      if (Y(a, k) != Y(b, k)) return Y(a, k) < Y(b, k);
    return false;
  });
  P.to_orig = ord;
  P.X.resize(n, Xn.cols());
  P.Y.resize(n, Y.cols());
  for (Index i = 0; i < n; ++i) {
    P.X.row(i) = Xn.row(ord[static_cast<std::size_t>(i)]);
    P.Y.row(i) = Y.row(ord[static_cast<std::size_t>(i)]);
  }
  P.sq = P.X.rowwise().squaredNorm();
  std::map<std::string, int> ids;  // ids by first appearance in the caller's order
  std::vector<int> gid_orig(un);
  for (std::size_t r = 0; r < un; ++r) {
    auto it = ids.try_emplace(groups[r], static_cast<int>(ids.size())).first;
    gid_orig[r] = it->second;
  }
  P.group.resize(un);
  P.members.assign(ids.size(), {});
  for (Index i = 0; i < n; ++i) {
    const int g = gid_orig[static_cast<std::size_t>(ord[static_cast<std::size_t>(i)])];
    P.group[static_cast<std::size_t>(i)] = g;
    P.members[static_cast<std::size_t>(g)].push_back(i);
  }
  P.singleton_groups = ids.size() == un;
  std::vector<Index> starts;
  for (Index i = 0; i < n; ++i)
    if (i == 0 || P.Y.row(i) != P.Y.row(i - 1)) starts.push_back(i);
  P.patterns.resize(static_cast<Index>(starts.size()), Y.cols());
  for (std::size_t p = 0; p < starts.size(); ++p) P.patterns.row(static_cast<Index>(p)) = P.Y.row(starts[p]);
  starts.push_back(n);
  P.pstart = starts;
  P.label.resize(un);
  for (Index i = 0; i < n; ++i) P.label[static_cast<std::size_t>(i)] = argmax(P.Y.row(i));
  P.pattern.resize(un);
  for (std::size_t p = 0; p + 1 < P.pstart.size(); ++p)
    for (Index i = P.pstart[p]; i < P.pstart[p + 1]; ++i)
      P.pattern[static_cast<std::size_t>(i)] = static_cast<Index>(p);
  return P;
}

}  // namespace millnet::classifier::detail
