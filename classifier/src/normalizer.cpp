#include "millnet/classifier/normalizer.hpp"

#include <cmath>
#include <string>

#include "millnet/classifier/tolerances.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

Normalizer Normalizer::fit(const Eigen::MatrixXd& X) {
  if (X.rows() < 1 || X.cols() < 1) throw Error("normalizer: the input matrix is empty (expected N×D with N, D ≥ 1)");
  if (!X.allFinite()) throw Error("normalizer: the input matrix contains NaN or infinite values");
  Normalizer n;
  const double inv_n = 1.0 / static_cast<double>(X.rows());
  n.mean = X.colwise().sum() * inv_n;
  n.std.resize(X.cols());
  // Two-pass variance (mean first): O(N·D), no cancellation of E[x²] − E[x]².
  for (Eigen::Index c = 0; c < X.cols(); ++c) {
    const double var = (X.col(c).array() - n.mean(c)).square().sum() * inv_n;
    const double s = std::sqrt(var);
    n.std(c) = s < tol::kConstantColumnStd ? 1.0 : s;
  }
  return n;
}

Eigen::MatrixXd Normalizer::apply(const Eigen::MatrixXd& X) const {
  if (X.cols() != mean.size())
    throw Error("normalizer: input has " + std::to_string(X.cols()) + " columns, the model expects " +
                std::to_string(mean.size()));
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (Eigen::Index c = 0; c < X.cols(); ++c) out.col(c) = (X.col(c).array() - mean(c)) / std(c);
  return out;
}

}  // namespace millnet::classifier
