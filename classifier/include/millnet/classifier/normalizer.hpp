#pragma once
// Statistical (z-score) normalization of the network's inputs, as Korosec & Kopac do before
// computing distances: x' = (x - mean) / std per input column.
#include <Eigen/Dense>

namespace millnet::classifier {

/// Per-column mean and population standard deviation (divisor N). A constant column (std below
/// tol::kConstantColumnStd) gets std = 1: it then maps to 0 for the stored set and contributes
/// (x - mean)² to the distance of a new input, in its raw units. Saved with the model.
struct Normalizer {
  Eigen::RowVectorXd mean;  ///< 1×D
  Eigen::RowVectorXd std;   ///< 1×D, every entry > 0

  /// Fits mean/std of X (N×D, rows = vectors, N ≥ 1). Throws millnet::Error on empty/non-finite X.
  [[nodiscard]] static Normalizer fit(const Eigen::MatrixXd& X);
  /// Returns (X - mean) / std row by row; X must have D columns (throws millnet::Error otherwise).
  [[nodiscard]] Eigen::MatrixXd apply(const Eigen::MatrixXd& X) const;
  [[nodiscard]] Eigen::Index dims() const { return mean.size(); }
};

}  // namespace millnet::classifier
