#pragma once
// Private engine of the classifier: the stored set in the order the kernels like, and the blocked
// d² pass every computation over stored × query pairs goes through.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace millnet::classifier::detail {

using Eigen::Index;

/// Row-major: one stored vector per contiguous row, so that a GEMM tile of stored rows is one
/// contiguous block (measured ≈ 8 % faster packing than the column-major tile).
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The stored set, permuted so that vectors with identical output rows ("patterns", = classes
/// for one-hot outputs) are contiguous: Σ_j s_j·y_j then costs one add per stored vector and a
/// P×K combination, instead of K multiply-adds per stored vector.
struct Prepared {
  RowMatrixXd X;                            ///< N×D normalized inputs, internal order
  Eigen::VectorXd sq;                       ///< N squared norms of X's rows
  Eigen::MatrixXd Y;                        ///< N×K outputs, internal order
  std::vector<Index> to_orig;               ///< internal index → caller's row
  std::vector<int> group;                   ///< internal index → group id (ids by first appearance)
  std::vector<std::vector<Index>> members;  ///< group id → internal indices (ascending)
  std::vector<Index> pstart;                ///< P+1 offsets of the pattern runs
  Eigen::MatrixXd patterns;                 ///< P×K distinct output rows
  std::vector<Index> label;                 ///< internal index → argmax of its output row
  std::vector<Index> pattern;               ///< internal index → its pattern run (row of `patterns`)
  bool singleton_groups = false;            ///< every group has one member (part-out == vector-out)
};

/// Validates shapes/finiteness (throws millnet::Error naming the argument) and builds Prepared.
/// O(N log N · K + N·D).
Prepared prepare(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y, const std::vector<std::string>& groups);

/// Index of the first maximum.
template <class Row>
Index argmax(const Row& r) {
  Index best = 0;
  for (Index k = 1; k < r.size(); ++k)
    if (r(k) > r(best)) best = k;
  return best;
}

/// Calls fn(block, row0, rows, D2) for every block of `block_rows` query rows, where D2 (N×rows)
/// holds in column c the squared distances of query row0+c to all N stored rows, computed as
/// ‖s‖² + ‖q‖² − 2 s·q by one GEMM per block (clamped at 0). Blocks run in parallel (OpenMP,
/// dynamic schedule); fn must write only block- or row-owned slots and must not throw.
/// Work O(N·M·D); memory O(N·block_rows) per thread.
/// Below this many pair evaluations a pass runs on one thread: waking a team costs more than the
/// work (and results do not depend on it: blocks are fixed by block_rows).
inline constexpr double kParallelWork = 1 << 16;
/// Stored rows per GEMM tile of for_each_d2_block.
inline constexpr Index kGemmTileRows = 256;

template <class MS, class MQ, class Fn>
void for_each_d2_block(const MS& S, const Eigen::VectorXd& sqS, const MQ& Q, const Eigen::VectorXd& sqQ,
                       Index block_rows, Fn&& fn) {
  const Index M = Q.rows();
  const Index nb = (M + block_rows - 1) / block_rows;
  const bool parallel = static_cast<double>(S.rows()) * static_cast<double>(M) > kParallelWork;
  if (nb == 1 && parallel) {
    // One block (a few query rows, e.g. one part's variants against the whole library): its tiles
    // in parallel instead, each tile's GEMM on its own thread. Left to itself, Eigen would split
    // every small tile product over a new team: measured 3.6× slower on 2 threads than on one
    // (bench_classifier BM_PredictPart: 38 ms → 10.6 ms on one thread). Same products, same bits.
    const Index tiles = (S.rows() + kGemmTileRows - 1) / kGemmTileRows;
    Eigen::MatrixXd D2(S.rows(), M);
    const Eigen::MatrixXd Qt = Q.transpose();
#pragma omp parallel for schedule(static)
    for (Index t = 0; t < tiles; ++t) {
      const Index t0 = t * kGemmTileRows, tr = std::min(kGemmTileRows, S.rows() - t0);
      const Eigen::MatrixXd T = S.middleRows(t0, tr) * Qt;
      for (Index c = 0; c < M; ++c)
        D2.col(c).segment(t0, tr) = ((sqS.segment(t0, tr).array() + sqQ(c)) - 2.0 * T.col(c).array()).max(0.0);
    }
    fn(Index{0}, Index{0}, M, D2);
    return;
  }
#pragma omp parallel if (nb > 1 && parallel)
  {
    Eigen::MatrixXd D2, T, Qt;
#pragma omp for schedule(dynamic, 1)
    for (Index b = 0; b < nb; ++b) {
      const Index r0 = b * block_rows;
      const Index rows = std::min(block_rows, M - r0);
      D2.resize(S.rows(), rows);
      Qt = Q.middleRows(r0, rows).transpose();
      // In tiles of kGemmTileRows stored rows, each finished into D2 while it is in cache: both
      // GEMM operands of a tile stay in L2, and D2 is written once (one N-row product re-packs
      // all of S per block and writes D2 three times: zeroing, product, finishing).
      // Measured: 1.3–1.5× the GEMM throughput.
      for (Index t0 = 0; t0 < S.rows(); t0 += kGemmTileRows) {
        const Index tr = std::min(kGemmTileRows, S.rows() - t0);
        T.resize(tr, rows);
        T.noalias() = S.middleRows(t0, tr) * Qt;
        for (Index c = 0; c < rows; ++c)
          D2.col(c).segment(t0, tr) = ((sqS.segment(t0, tr).array() + sqQ(r0 + c)) - 2.0 * T.col(c).array()).max(0.0);
      }
      fn(b, r0, rows, D2);
    }
  }
}

// Buffers of nearest_cut.
struct NearestBuffers {
  std::vector<double> sample, vals;
  std::vector<std::int32_t> idx;
};

// The R-th smallest of d[0..n) (0-based; +inf when R ≥ n), exactly what std::nth_element gives,
// and in B.idx, ascending, the indices j of a superset of {d_j < it}. A pivot from a strided
// sample (its rank chosen so that ≈ 3R values lie below it) bounds the candidates; selection then
// runs on those few. If fewer than R + 1 values lie at or below the pivot, every index is a
// candidate. Expected O(n) with a small constant (one branch-free pass), against ≈ 11 ns per value
// for nth_element over the whole row.
inline double nearest_cut(const double* d, Index n, Index R, NearestBuffers& B) {
  B.idx.resize(static_cast<std::size_t>(n));
  Index cnt = 0;
  if (R >= n) {
    for (Index j = 0; j < n; ++j) B.idx[static_cast<std::size_t>(j)] = static_cast<std::int32_t>(j);
    return std::numeric_limits<double>::infinity();
  }
  double pivot = std::numeric_limits<double>::infinity();
  const Index stride = std::max<Index>(1, n / (4 * (R + 1)));
  if (stride >= 4) {
    B.sample.clear();
    for (Index j = 0; j < n; j += stride) B.sample.push_back(d[j]);
    const auto k = std::min<std::size_t>(B.sample.size() - 1, static_cast<std::size_t>(3 * (R + 1) / stride));
    std::nth_element(B.sample.begin(), B.sample.begin() + static_cast<std::ptrdiff_t>(k), B.sample.end());
    pivot = B.sample[k];
    for (Index j = 0; j < n; ++j) {  // branch-free compaction
      B.idx[static_cast<std::size_t>(cnt)] = static_cast<std::int32_t>(j);
      cnt += d[j] <= pivot ? 1 : 0;
    }
  }
  if (cnt < R + 1) {  // pivot too low (or no sample): every value is a candidate
    for (Index j = 0; j < n; ++j) B.idx[static_cast<std::size_t>(j)] = static_cast<std::int32_t>(j);
    cnt = n;
  }
  B.idx.resize(static_cast<std::size_t>(cnt));
  // all values ≤ pivot are candidates and there are ≥ R + 1 of them, so the R + 1 smallest of the
  // row are among them: the R-th smallest candidate is the row's
  B.vals.resize(static_cast<std::size_t>(cnt));
  for (std::size_t t = 0; t < B.idx.size(); ++t) B.vals[t] = d[B.idx[t]];
  std::nth_element(B.vals.begin(), B.vals.begin() + static_cast<std::ptrdiff_t>(R), B.vals.end());
  return B.vals[static_cast<std::size_t>(R)];
}

}  // namespace millnet::classifier::detail
