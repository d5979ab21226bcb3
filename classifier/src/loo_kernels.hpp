#pragma once
// Private kernels of the leave-one-out α search (loo.cpp): per-row exps and sums, shared by the
// three exclusion modes, and the blocked passes over all N² pairs built from them
// (loo_kernels.cpp). Every reduction is a per-block partial sum combined in block order.
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "engine.hpp"
#include "simd.hpp"
#include "millnet/classifier/tolerances.hpp"

namespace millnet::classifier::detail::loo {

using Eigen::ArrayXd;
using Eigen::MatrixXd;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

enum Mode : int { kPart = 0, kVector = 1, kFiltration = 2 };

struct Figures {
  double rms = 0;
  double accuracy = 0;
};

struct PartialSums {
  double err = 0;
  Index correct = 0;
};

// Figures of one slot (a candidate, a grid point) from per-block rows of slots, in block order.
Figures finish_slot(const std::vector<std::vector<PartialSums>>& blocks, std::size_t slot, Index n, Index k);

// e = exp(−δ·u) with values below tol::kSimilarityFloor set to 0 (simd.hpp). O(N).
void exp_floored(const ArrayXd& delta, double u, ArrayXd& e);

// One full blocked pass at one α with exact exps: O(N²·D + N²).
Figures full_pass(const Prepared& P, double alpha, int mode, Index block_rows, MatrixXd* outputs);

// The R nearest stored vectors (self and siblings included) of every stored vector, CSR.
struct Cache {
  std::vector<Index> offset;  // N+1
  std::vector<double> d2;
  std::vector<std::int32_t> j;
  std::vector<double> dplus;             // smallest d² NOT kept (+inf when the row is complete)
  std::vector<double> m[3];              // per mode: the row minimum the network subtracts
  double covered[3] = {0, 0, 0};         // α up to which the cache is exact to double precision, per mode
  double covered_refine[3] = {0, 0, 0};  // same with tol::kRefineTruncationMargin (refinement only)
};

// One pass over the cache at one α (exact where the cache covers α): O(N·R).
Figures cache_pass(const Prepared& P, const Cache& C, double alpha, int mode, Index block_rows, MatrixXd* outputs);

// Figures at one α on the cache when it is exact there, else by a full pass (counted).
struct Evaluator {
  const Prepared& P;
  const Cache& C;
  Index block_rows;
  int* full_passes;
  bool refining = false;  // golden-section evaluations may use the looser cache bound
  Figures operator()(double alpha, int mode, MatrixXd* outputs = nullptr) const {
    if (alpha <= (refining ? C.covered_refine[mode] : C.covered[mode]))
      return cache_pass(P, C, alpha, mode, block_rows, outputs);
    ++*full_passes;
    return full_pass(P, alpha, mode, block_rows, outputs);
  }
};

// ---- shared-exp kernels ------------------------------------------------------------------------
// The three sets a stored vector i is predicted from differ only by its own group: part-out uses
// the other groups (shift m_p = their nearest d²), vector-out adds i's siblings (shift
// m_v = min(m_p, nearest sibling)), filtration adds i itself (shift m_f = min over all). So one
// exp per pair over the other groups, with shift m_p, serves all three: the other-group sums are
// rescaled by exp(−(m_p − m_shift)/α) (one exp per row and α), and the few siblings (group size
// |G|) get their own scalar exps. Rounding: a few ulp relative, like a direct exp.
struct RowState {
  ArrayXd delta;  // N: d² − m_p over other groups, +inf on i's own group
  double mp = 0, mv = 0, mf = 0;
  std::vector<double> gdelta;  // siblings j ≠ i: d² − m_v
  std::vector<Index> gpat;     // their pattern runs
  double self_delta = 0;       // d²_ii − m_f (≈ 0)
  Index self_pat = 0;
};

// Loads stored vector i's d² row d (N) into s: the shifts and the other-group deltas. O(N + |G|).
void load_row(const Prepared& P, const double* d, Index i, RowState& s);

// Power sums over one pattern run [a, b) in ONE sweep: out[t·stride] = Σ_j x_j(t) for t < steps,
// with x_j(0) = e_j and x_j(t+1) = x_j(t)² (Square: the α, α/2, α/4 … chains) or x_j(t)·r_j (a
// grid even in 1/α). Values that underflow become exactly 0: the sweep runs with flush-to-zero
// (simd.hpp; neglected mass < N·2.3e-308 relative to the nearest vector's 1), or, on targets
// without it, against tol::kSimilarityFloor. Groups of kGroups·kLanes values stay in registers
// across the steps and stop once all of them are 0, so distant pairs cost only their few
// non-negligible steps. Fixed summation order (groups, then lanes combined 0…kLanes−1):
// independent of threads. O((b − a)·steps).
template <bool Square>
void power_sums(const double* e, const double* rr, Index a, Index b, Index steps, double* out, Index stride,
                std::vector<Lane>& acc) {
  const detail::FlushToZero ftz;
  acc.assign(static_cast<std::size_t>(steps), Lane{});
  const Lane zero{};
  const Lane floor = zero + tol::kSimilarityFloor;
  const auto step = [&](Lane& x, const Lane& y) {
    if constexpr (Square)
      x = x * x;
    else
      x = x * y;
    if constexpr (!detail::kFlushesToZero) x = x < floor ? zero : x;
  };
  // 8 independent lane groups per iteration: each step is a dependent multiply chain, so
  // several in flight hide its latency, and the per-step accumulator update is shared by all
  constexpr int kGroups = 8;
  Index j = a;
  for (; j + kGroups * kLanes <= b; j += kGroups * kLanes) {
    Lane x[kGroups], y[kGroups] = {};
    std::memcpy(x, e + j, sizeof(x));
    if constexpr (!Square) std::memcpy(y, rr + j, sizeof(y));
    for (Index t = 0; t < steps; ++t) {
      Lane sum = ((x[0] + x[1]) + (x[2] + x[3])) + ((x[4] + x[5]) + (x[6] + x[7]));
      acc[static_cast<std::size_t>(t)] += sum;
      for (int g = 0; g < kGroups; ++g) step(x[g], y[g]);
      // every 4th step (a horizontal test costs more than a step): all lanes 0 (x ≥ 0) means
      // the remaining steps add nothing
      if ((t & 3) == 3) {
        const Lane m = ((x[0] + x[1]) + (x[2] + x[3])) + ((x[4] + x[5]) + (x[6] + x[7]));
        bool any = false;
        for (int l = 0; l < kLanes; ++l) any |= m[l] != 0.0;
        if (!any) break;
      }
    }
  }
  for (; j + kLanes <= b; j += kLanes) {
    Lane x, y{};
    std::memcpy(&x, e + j, sizeof(Lane));
    if constexpr (!Square) std::memcpy(&y, rr + j, sizeof(Lane));
    for (Index t = 0; t < steps; ++t) {
      acc[static_cast<std::size_t>(t)] += x;
      step(x, y);
    }
  }
  double* acc0 = reinterpret_cast<double*>(acc.data());  // lane 0 of step t at acc0[t·kLanes]
  for (; j < b; ++j) {                                   // tail: lane 0
    double x = e[j];
    for (Index t = 0; t < steps && x != 0.0; ++t) {
      acc0[t * kLanes] += x;
      const double v = Square ? x * x : x * rr[Square ? 0 : j];
      x = !detail::kFlushesToZero && v < tol::kSimilarityFloor ? 0.0 : v;
    }
  }
  for (Index t = 0; t < steps; ++t) {
    double sum = 0;
    for (int l = 0; l < kLanes; ++l) sum += acc[static_cast<std::size_t>(t)][l];  // fixed order
    out[t * stride] = sum;
  }
}

// Part-out and vector-out predictions of row i at the inverse widths u[0..nu), given the
// other-group sums Sng (nu×P, shift m_p); adds the siblings' exps. O(nu·(|G| + P·K)).
void score_modes(const Prepared& P, const RowState& s, Index i, const double* u, Index nu, const double* Sng,
                 PartialSums* ps_part, PartialSums* ps_vector, Eigen::RowVectorXd& out, std::vector<double>& tmp,
                 std::vector<double>& sib);

struct GridSpec {
  int mode = kPart;
  double u0 = 0, h = 0;
  Index points = 0;
};

// A row's shifts and its own term (load_row), kept for its outputs at any α.
struct RowShifts {
  double mp = 0, mv = 0, mf = 0, self_delta = 0;
  Index self_pat = 0;
};

// Row sums kept from a grid pass for one spec, so that the outputs at any of its points need no
// further pass: N·points·2P doubles.
struct GridStore {
  std::vector<double> S, Sg;     // [(i·points + t)·P + p]
  std::vector<RowShifts> shift;  // N
};

// Per-spec, per-block, per-point partial sums of a grid evaluation.
using GridParts = std::vector<std::vector<std::vector<PartialSums>>>;  // [spec][block][point]

// Zeroed grid sums for nb blocks.
GridParts make_grid_parts(const std::vector<GridSpec>& specs, Index nb);

// Per-thread buffers of the grid kernel.
struct GridBuffers {
  ArrayXd e, r;
  std::vector<double> tmp, S, u, sib;
  std::vector<Lane> acc;
};

// Grid evaluation of one loaded row for every spec into ps[g] (points entries each), keeping its
// sums in stores[g] when that store is allocated. O(N·Σ(2 + points)).
void grid_row(const Prepared& P, const RowState& s, Index i, const std::vector<GridSpec>& specs,
              std::vector<GridStore>& stores, GridParts& parts, Index b, GridBuffers& B, Eigen::RowVectorXd& out);

// Figures per spec and point from per-block grid sums, blocks combined in order.
std::vector<std::vector<Figures>> grid_results(const GridParts& parts, const std::vector<GridSpec>& specs, Index n,
                                               Index k);

// One full pass evaluating, for each requested mode, G inverse widths u_g = u0 + g·h exactly
// (e_g = e_0·r^g with r = exp(−δ·h): 2 exps per pair and mode, then one multiply per point;
// ≤ G ulp rounding), keeping the sums of the specs whose store is allocated. Per-block partial
// sums, combined in block order: figures per spec and point. O(N²·D + N²·Σ(2 + points)).
std::vector<std::vector<Figures>> grid_pass(const Prepared& P, const std::vector<GridSpec>& specs, Index block_rows,
                                            std::vector<GridStore>& stores);

// Outputs and both modes' figures at point t of a stored grid. O(N·P·K).
void outputs_from_store(const Prepared& P, const GridSpec& sp, const GridStore& st, Index t, int chosen, Figures fig[2],
                        MatrixXd& verification, MatrixXd& filtration);

// One full pass at α giving part-out and vector-out figures and the chosen mode's verification
// and the filtration outputs (caller's row order): one exp per pair. O(N²·D + N²).
void final_pass(const Prepared& P, double alpha, int chosen, Index block_rows, Figures fig[2], MatrixXd& verification,
                MatrixXd& filtration);

}  // namespace millnet::classifier::detail::loo
