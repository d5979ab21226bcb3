#pragma once
// Shared by the classifier tests: a brute-force reference of the network and leave-one-out outputs,
// clustered synthetic data sets, and a bitwise comparison.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace millnet::classifier::test {

using Eigen::Index;
using Eigen::MatrixXd;

// Brute-force reference: full N×N (or M×N) distances by explicit loops, std::exp, no blocks.
// mode: 0 = part-out, 1 = vector-out, 2 = filtration.
inline MatrixXd reference_outputs(const MatrixXd& X, const MatrixXd& Y, const std::vector<std::string>& g, double alpha,
                                  int mode) {
  const Index n = X.rows();
  MatrixXd out = MatrixXd::Zero(n, Y.cols());
  for (Index i = 0; i < n; ++i) {
    std::vector<double> d(static_cast<std::size_t>(n));
    std::vector<bool> use(static_cast<std::size_t>(n), true);
    double m = INFINITY;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      d[uj] = (X.row(i) - X.row(j)).squaredNorm();
      if (mode == 0 && g[uj] == g[static_cast<std::size_t>(i)]) use[uj] = false;
      if (mode == 1 && j == i) use[uj] = false;
      if (use[uj]) m = std::min(m, d[uj]);
    }
    double tot = 0;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      if (!use[uj]) continue;
      const double s = std::exp(-(d[uj] - m) / alpha);
      tot += s;
      out.row(i) += s * Y.row(j);
    }
    out.row(i) /= tot;
  }
  return out;
}

// Clustered synthetic set: `classes` centres in D dims (spread `sep`), parts of `per_part` vectors
// around a part centre (spread `part_noise` around its class centre, `vec_noise` within the part).
struct Synthetic {
  MatrixXd X, Y;
  std::vector<std::string> groups;
};
inline Synthetic make_clusters(unsigned seed, int classes, int parts_per_class, int per_part, Index D, double sep,
                               double part_noise, double vec_noise, bool random_labels = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N01(0.0, 1.0);
  std::uniform_int_distribution<int> cls(0, classes - 1);
  MatrixXd centres(classes, D);
  for (Index i = 0; i < centres.size(); ++i) centres.data()[i] = sep * N01(rng);
  Synthetic s;
  const int n = classes * parts_per_class * per_part;
  s.X.resize(n, D);
  s.Y = MatrixXd::Zero(n, classes);
  int row = 0;
  for (int c = 0; c < classes; ++c)
    for (int p = 0; p < parts_per_class; ++p) {
      Eigen::RowVectorXd pc(D);
      for (Index k = 0; k < D; ++k) pc(k) = centres(c, k) + part_noise * N01(rng);
      const int label = random_labels ? cls(rng) : c;
      for (int v = 0; v < per_part; ++v, ++row) {
        for (Index k = 0; k < D; ++k) s.X(row, k) = pc(k) + vec_noise * N01(rng);
        s.Y(row, label) = 1.0;
        s.groups.push_back("part" + std::to_string(c) + "_" + std::to_string(p));
      }
    }
  return s;
}

inline bool bitwise_equal(const MatrixXd& a, const MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace millnet::classifier::test
