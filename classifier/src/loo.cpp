// Leave-one-out selection of the penalty coefficient α (Korosec & Kopac, "prevents over-training":
// delete a case, predict it from the rest, minimize the RMS verification error).
//
// Pass structure (N stored vectors, D inputs, C candidates, q steps per octave, R cache size,
// G grid points, P distinct output rows). A "full pass" is one blocked N×N×D GEMM; the kernels
// share one exp per pair between part-out, vector-out and filtration (see RowState).
//  1. Scan: one full pass. For each stored vector the C candidates of both modes come from the
//     same d² column: the candidates form q chains α, α/2, α/4, … so exp(−δ/(α/2)) = exp(−δ/α)²
//     — one exp per pair per chain, then a square and an add per pair and candidate, in one
//     sweep with early exit once a lane group underflows: O(N²·(q + C)). The R nearest d² of
//     every vector are kept (O(N·R) memory).
//  2. Refinement per mode around its best candidate: golden section on log α on the cache when
//     the cache is exact over the whole bracket (cheap: O(N·R) per evaluation); otherwise ONE
//     full pass for all such modes evaluating G points even in 1/α with one step over
//     [α_lo, α_hi], α_best among them (exact exps: 2 per pair and mode, then one multiply per
//     point); the chosen mode's run sums are kept (N·G·2P doubles) so its outputs need no
//     further pass. A pre-scan of every k-th vector (1/k of a pass) predicts each mode's best
//     candidate and whether the cache will cover its bracket, so that the scan pass evaluates
//     the grids too: the refinement's own pass is needed only when the prediction fails.
//  3. Filtration and verification outputs at the chosen α: from the kept sums, from the cache
//     when exact, else one full pass for both modes and the filtration together.
// So 1–3 full passes in all (1 + 1/k in the usual case), never an N×N matrix.
// Per pair, the work is the GEMM's 2D flops, q + 2·(modes on a grid) exps (simd.hpp) and the
// multiply-adds of the chains; the GEMM runs in L2-sized tiles (engine.hpp).
// Determinism: blocks are fixed by block_rows, never by the thread count; every reduction is a
// per-block partial sum combined in block order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "engine.hpp"
#include "simd.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/tolerances.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

using detail::Index;
using detail::Prepared;
using Eigen::ArrayXd;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum Mode : int { kPart = 0, kVector = 1, kFiltration = 2 };

struct Figures {
  double rms = 0;
  double accuracy = 0;
};

// Sets the excluded entries of stored-vector i's d² row to +inf for the mode. O(group size).
void mask(const Prepared& P, Index i, int mode, ArrayXd& w) {
  if (mode == kPart) {
    for (Index j : P.members[static_cast<std::size_t>(P.group[static_cast<std::size_t>(i)])]) w(j) = kInf;
  } else if (mode == kVector) {
    w(i) = kInf;
  }
}

struct PartialSums {
  double err = 0;
  Index correct = 0;
};

Figures finish(const std::vector<PartialSums>& blocks, Index n, Index k) {
  double err = 0;
  Index correct = 0;
  for (const auto& b : blocks) {  // block order: identical for any thread count
    err += b.err;
    correct += b.correct;
  }
  return {std::sqrt(err / static_cast<double>(n * k)), static_cast<double>(correct) / static_cast<double>(n)};
}

// Figures of one slot (a candidate, a grid point) from per-block rows of slots, in block order.
Figures finish_slot(const std::vector<std::vector<PartialSums>>& blocks, std::size_t slot, Index n, Index k) {
  std::vector<PartialSums> col(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) col[b] = blocks[b][slot];
  return finish(col, n, k);
}

// S[p] = Σ of e over pattern run p. O(N), vectorized.
void run_sums(const Prepared& P, const ArrayXd& e, double* S) {
  const Index np = P.patterns.rows();
  for (Index p = 0; p < np; ++p) {
    const Index a = P.pstart[static_cast<std::size_t>(p)];
    S[p] = e.segment(a, P.pstart[static_cast<std::size_t>(p) + 1] - a).sum();
  }
}

// Σ_p S_p·pattern_p / Σ_p S_p, skipping zero weights. O(P·K).
void combine_sums(const Prepared& P, const double* S, Eigen::RowVectorXd& out) {
  out.setZero();
  double tot = 0;
  for (Index p = 0; p < P.patterns.rows(); ++p) {
    if (S[p] != 0.0) out.noalias() += S[p] * P.patterns.row(p);
    tot += S[p];
  }
  out /= tot;
}

// e = exp(−δ·u) with values below tol::kSimilarityFloor set to 0 (simd.hpp). O(N).
void exp_floored(const ArrayXd& delta, double u, ArrayXd& e) {
  e.resize(delta.size());
  detail::exp_neg_scaled(delta.data(), u, tol::kSimilarityFloor, e.data(), delta.size());
}

// Scores row i's prediction `out` into ps.
void score(const Prepared& P, Index i, const Eigen::RowVectorXd& out, PartialSums& ps) {
  ps.err += (out - P.Y.row(i)).squaredNorm();
  ps.correct += detail::argmax(out) == P.label[static_cast<std::size_t>(i)] ? 1 : 0;
}

// One full blocked pass at one α with exact exps: O(N²·D + N²).
Figures full_pass(const Prepared& P, double alpha, int mode, Index block_rows, MatrixXd* outputs) {
  const Index n = P.X.rows(), k = P.Y.cols();
  const Index nb = (n + block_rows - 1) / block_rows;
  std::vector<PartialSums> parts(static_cast<std::size_t>(nb));
  const double inv_alpha = 1.0 / alpha;
  detail::for_each_d2_block(P.X, P.sq, P.X, P.sq, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
    ArrayXd w, e;
    std::vector<double> S(static_cast<std::size_t>(P.patterns.rows()));
    Eigen::RowVectorXd out(k);
    PartialSums ps;
    for (Index c = 0; c < rows; ++c) {
      const Index i = r0 + c;
      w = D2.col(c).array();
      mask(P, i, mode, w);
      w -= w.minCoeff();
      exp_floored(w, inv_alpha, e);  // masked (+inf) entries become 0
      run_sums(P, e, S.data());
      combine_sums(P, S.data(), out);
      score(P, i, out, ps);
      if (outputs) outputs->row(P.to_orig[static_cast<std::size_t>(i)]) = out;
    }
    parts[static_cast<std::size_t>(b)] = ps;
  });
  return finish(parts, n, k);
}

// The R nearest stored vectors (self and siblings included) of every stored vector, CSR.
struct Cache {
  std::vector<Index> offset;  // N+1
  std::vector<double> d2;
  std::vector<std::int32_t> j;
  std::vector<double> dplus;  // smallest d² NOT kept (+inf when the row is complete)
  std::vector<double> m[3];   // per mode: the row minimum the network subtracts
  double covered[3] = {0, 0, 0};  // α up to which the cache is exact to double precision, per mode
  double covered_refine[3] = {0, 0, 0};  // same with tol::kRefineTruncationMargin (refinement only)
};

Figures cache_pass(const Prepared& P, const Cache& C, double alpha, int mode, Index block_rows, MatrixXd* outputs) {
  const Index n = P.X.rows(), k = P.Y.cols();
  const Index nb = (n + block_rows - 1) / block_rows;
  std::vector<PartialSums> parts(static_cast<std::size_t>(nb));
  const double inv_alpha = 1.0 / alpha;
#pragma omp parallel for schedule(dynamic, 1) if (static_cast<double>(C.d2.size()) > detail::kParallelWork)
  for (Index b = 0; b < nb; ++b) {  // O(block_rows · R) per block
    Eigen::RowVectorXd out(k);
    PartialSums ps;
    std::vector<double> e, S(static_cast<std::size_t>(P.patterns.rows()));  // S: pattern-run sums
    const Index r1 = std::min(n, (b + 1) * block_rows);
    for (Index i = b * block_rows; i < r1; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const int gi = P.group[ui];
      const double m = C.m[mode][ui];
      const Index t0 = C.offset[ui], len = C.offset[ui + 1] - t0;
      e.resize(static_cast<std::size_t>(len));
      // excluded entries may lie below m: clamped to δ = 0, their exps are computed but never used
      for (Index t = 0; t < len; ++t)
        e[static_cast<std::size_t>(t)] = std::max(C.d2[static_cast<std::size_t>(t0 + t)] - m, 0.0);
      detail::exp_neg_scaled(e.data(), inv_alpha, tol::kSimilarityFloor, e.data(), len);
      std::fill(S.begin(), S.end(), 0.0);
      for (Index t = t0; t < t0 + len; ++t) {
        const auto jj = static_cast<std::size_t>(C.j[static_cast<std::size_t>(t)]);
        if ((mode == kPart && P.group[jj] == gi) || (mode == kVector && static_cast<Index>(jj) == i)) continue;
        S[static_cast<std::size_t>(P.pattern[jj])] += e[static_cast<std::size_t>(t - t0)];
      }
      combine_sums(P, S.data(), out);
      score(P, i, out, ps);
      if (outputs) outputs->row(P.to_orig[ui]) = out;
    }
    parts[static_cast<std::size_t>(b)] = ps;
  }
  return finish(parts, n, k);
}

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
  ArrayXd delta;              // N: d² − m_p over other groups, +inf on i's own group
  double mp = 0, mv = 0, mf = 0;
  std::vector<double> gdelta;  // siblings j ≠ i: d² − m_v
  std::vector<Index> gpat;     // their pattern runs
  double self_delta = 0;       // d²_ii − m_f (≈ 0)
  Index self_pat = 0;
};

// O(N + |G|).
void load_row(const Prepared& P, const double* d, Index i, RowState& s) {
  const Index n = P.X.rows();
  s.delta = Eigen::Map<const ArrayXd>(d, n);
  const auto& mem = P.members[static_cast<std::size_t>(P.group[static_cast<std::size_t>(i)])];
  for (Index j : mem) s.delta(j) = kInf;
  s.mp = s.delta.minCoeff();
  s.mv = s.mp;
  for (Index j : mem)
    if (j != i) s.mv = std::min(s.mv, d[j]);
  s.mf = std::min(s.mv, d[i]);
  s.delta -= s.mp;
  s.gdelta.clear();
  s.gpat.clear();
  for (Index j : mem)
    if (j != i) {
      s.gdelta.push_back(d[j] - s.mv);
      s.gpat.push_back(P.pattern[static_cast<std::size_t>(j)]);
    }
  s.self_delta = d[i] - s.mf;
  s.self_pat = P.pattern[static_cast<std::size_t>(i)];
}

// Power sums over one pattern run [a, b) in ONE sweep: out[t·stride] = Σ_j x_j(t) for t < steps,
// with x_j(0) = e_j and x_j(t+1) = x_j(t)² (Square: the α, α/2, α/4 … chains) or x_j(t)·r_j (a
// grid even in 1/α). Values that underflow become exactly 0: the sweep runs with flush-to-zero
// (simd.hpp; neglected mass < N·2.3e-308 relative to the nearest vector's 1), or, on targets
// without it, against tol::kSimilarityFloor. Groups of kGroups·kLanes values stay in registers
// across the steps and stop once all of them are 0, so distant pairs cost only their few
// non-negligible steps. Fixed summation order (groups, then lanes combined 0…kLanes−1):
// independent of threads. O((b − a)·steps).
using detail::kLanes;
using detail::Lane;
template <bool Square>
void power_sums(const double* e, const double* rr, Index a, Index b, Index steps, double* out, Index stride,
                std::vector<Lane>& acc) {
  const detail::FlushToZero ftz;
  acc.assign(static_cast<std::size_t>(steps), Lane{});
  const Lane zero{};
  const Lane floor = zero + tol::kSimilarityFloor;
  const auto step = [&](Lane& x, const Lane& y) {
    if constexpr (Square) x = x * x; else x = x * y;
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
  for (; j < b; ++j) {  // tail: lane 0
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

// Sibling run sums at u: O(|G|) exps.
void sibling_sums(const RowState& s, double u, double* Sg, Index np, std::vector<double>& sib) {
  std::fill(Sg, Sg + np, 0.0);
  sib.resize(s.gdelta.size());
  detail::exp_neg_scaled(s.gdelta.data(), u, tol::kSimilarityFloor, sib.data(), static_cast<Index>(sib.size()));
  for (std::size_t t = 0; t < sib.size(); ++t) Sg[s.gpat[t]] += sib[t];
}

// Vector-out run sums at u: the other groups' sums S (shift m_p) rescaled to the shift m_v, plus
// the siblings' sums Sg (shift m_v). O(P).
void vector_sums(double mp, double mv, double u, const double* S, const double* Sg, Index np, double* T) {
  const double f = std::exp(-(mp - mv) * u);
  for (Index p = 0; p < np; ++p) T[p] = S[p] * f + Sg[p];
}

// Part-out and vector-out predictions of row i at the inverse widths u[0..nu), given the
// other-group sums Sng (nu×P, shift m_p); adds the siblings' exps. O(nu·(|G| + P·K)).
void score_modes(const Prepared& P, const RowState& s, Index i, const double* u, Index nu, const double* Sng,
                 PartialSums* ps_part, PartialSums* ps_vector, Eigen::RowVectorXd& out, std::vector<double>& tmp,
                 std::vector<double>& sib) {
  const Index np = P.patterns.rows();
  tmp.resize(2 * static_cast<std::size_t>(np));
  double* const Sg = tmp.data() + np;  // the siblings' run sums
  for (Index k = 0; k < nu; ++k) {
    const double* S = Sng + k * np;
    if (ps_part) {
      combine_sums(P, S, out);
      score(P, i, out, ps_part[k]);
    }
    if (ps_vector) {
      sibling_sums(s, u[k], Sg, np, sib);
      vector_sums(s.mp, s.mv, u[k], S, Sg, np, tmp.data());
      combine_sums(P, tmp.data(), out);
      score(P, i, out, ps_vector[k]);
    }
  }
}

struct GridSpec {
  int mode = kPart;
  double u0 = 0, h = 0;
  Index points = 0;
};

// Part-out, vector-out and filtration outputs of row i at inverse width u from its other-group
// run sums S (shift m_p) and sibling run sums Sg (shift m_v). O(P·K).
struct RowShifts {
  double mp = 0, mv = 0, mf = 0, self_delta = 0;
  Index self_pat = 0;
};
void final_row(const Prepared& P, const RowShifts& s, double u, const double* S, const double* Sg,
               Eigen::RowVectorXd& part, Eigen::RowVectorXd& vec, Eigen::RowVectorXd& fil, std::vector<double>& T) {
  const Index np = P.patterns.rows();
  T.resize(static_cast<std::size_t>(np));
  combine_sums(P, S, part);
  vector_sums(s.mp, s.mv, u, S, Sg, np, T.data());
  combine_sums(P, T.data(), vec);
  const double ff = std::exp(-(s.mp - s.mf) * u), fg = std::exp(-(s.mv - s.mf) * u);
  for (Index p = 0; p < np; ++p) T[static_cast<std::size_t>(p)] = S[p] * ff + Sg[p] * fg;
  T[static_cast<std::size_t>(s.self_pat)] += std::exp(-s.self_delta * u);
  combine_sums(P, T.data(), fil);
}

RowShifts shifts_of(const RowState& s) { return {s.mp, s.mv, s.mf, s.self_delta, s.self_pat}; }

// Row sums kept from a grid pass for one spec, so that the outputs at any of its points need no
// further pass: N·points·2P doubles.
struct GridStore {
  std::vector<double> S, Sg;  // [(i·points + t)·P + p]
  std::vector<RowShifts> shift;  // N
};

// One full pass evaluating, for each requested mode, G inverse widths u_g = u0 + g·h exactly
// (e_g = e_0·r^g with r = exp(−δ·h): 2 exps per pair and mode, then one multiply per point;
// ≤ G ulp rounding). Per-block partial sums, combined in block order. O(N²·D + N²·(2 + G)).
// parts[g][block][point] → figures per spec and point, blocks combined in order.
using GridParts = std::vector<std::vector<std::vector<PartialSums>>>;  // [spec][block][point]
GridParts make_grid_parts(const std::vector<GridSpec>& specs, Index nb) {
  GridParts parts(specs.size(), std::vector<std::vector<PartialSums>>(static_cast<std::size_t>(nb)));
  for (std::size_t g = 0; g < specs.size(); ++g)
    for (auto& v : parts[g]) v.assign(static_cast<std::size_t>(specs[g].points), {});
  return parts;
}

// Per-thread buffers of the grid kernel.
struct GridBuffers {
  ArrayXd e, r;
  std::vector<double> tmp, S, u, sib;
  std::vector<Lane> acc;
};

// Grid evaluation of one loaded row for every spec into ps[g] (points entries each), keeping its
// sums in stores[g] when that store is allocated. O(N·Σ(2 + points)).
void grid_row(const Prepared& P, const RowState& s, Index i, const std::vector<GridSpec>& specs,
              std::vector<GridStore>& stores, GridParts& parts, Index b, GridBuffers& B, Eigen::RowVectorXd& out) {
  const Index np = P.patterns.rows();
  for (std::size_t g = 0; g < specs.size(); ++g) {
    const GridSpec& sp = specs[g];
    B.S.assign(static_cast<std::size_t>(sp.points * np), 0.0);
    B.u.resize(static_cast<std::size_t>(sp.points));
    exp_floored(s.delta, sp.u0, B.e);
    // r below the floor: e·r is below it too and becomes 0 either way
    exp_floored(s.delta, sp.h, B.r);
    for (Index t = 0; t < sp.points; ++t) B.u[static_cast<std::size_t>(t)] = sp.u0 + static_cast<double>(t) * sp.h;
    for (Index p = 0; p < np; ++p)
      power_sums<false>(B.e.data(), B.r.data(), P.pstart[static_cast<std::size_t>(p)],
                        P.pstart[static_cast<std::size_t>(p) + 1], sp.points, B.S.data() + p, np, B.acc);
    GridStore& st = stores[g];
    if (!st.S.empty()) {  // keep this row's sums for the outputs at the chosen point
      const auto off = static_cast<std::size_t>(i * sp.points * np);
      std::copy(B.S.begin(), B.S.end(), st.S.begin() + static_cast<std::ptrdiff_t>(off));
      for (Index t = 0; t < sp.points; ++t)
        sibling_sums(s, B.u[static_cast<std::size_t>(t)], st.Sg.data() + off + static_cast<std::size_t>(t * np), np,
                     B.sib);
      st.shift[static_cast<std::size_t>(i)] = shifts_of(s);
    }
    PartialSums* q = parts[g][static_cast<std::size_t>(b)].data();
    score_modes(P, s, i, B.u.data(), sp.points, B.S.data(), sp.mode == kPart ? q : nullptr,
                sp.mode == kVector ? q : nullptr, out, B.tmp, B.sib);
  }
}

std::vector<std::vector<Figures>> grid_results(const GridParts& parts,
                                               const std::vector<GridSpec>& specs, Index n, Index k) {
  std::vector<std::vector<Figures>> res(specs.size());
  for (std::size_t g = 0; g < specs.size(); ++g)
    for (Index t = 0; t < specs[g].points; ++t) res[g].push_back(finish_slot(parts[g], static_cast<std::size_t>(t), n, k));
  return res;
}

// One full pass evaluating the grid specs. O(N²·D + N²·Σ(2 + points)).
std::vector<std::vector<Figures>> grid_pass(const Prepared& P, const std::vector<GridSpec>& specs, Index block_rows,
                                            std::vector<GridStore>& stores) {
  const Index n = P.X.rows(), k = P.Y.cols();
  const Index nb = (n + block_rows - 1) / block_rows;
  GridParts parts = make_grid_parts(specs, nb);
  detail::for_each_d2_block(P.X, P.sq, P.X, P.sq, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
    RowState s;
    GridBuffers B;
    Eigen::RowVectorXd out(k);
    for (Index c = 0; c < rows; ++c) {
      const Index i = r0 + c;
      load_row(P, D2.col(c).data(), i, s);
      grid_row(P, s, i, specs, stores, parts, b, B, out);
    }
  });
  return grid_results(parts, specs, n, k);
}

// Outputs and both modes' figures at point t of a stored grid. O(N·P·K).
void outputs_from_store(const Prepared& P, const GridSpec& sp, const GridStore& st, Index t, int chosen, Figures fig[2],
                        MatrixXd& verification, MatrixXd& filtration) {
  const Index n = P.X.rows(), k = P.Y.cols(), np = P.patterns.rows();
  Eigen::RowVectorXd part(k), vec(k), fil(k);
  std::vector<double> T;
  PartialSums ps[2];
  const double u = sp.u0 + static_cast<double>(t) * sp.h;
  for (Index i = 0; i < n; ++i) {
    const auto off = static_cast<std::size_t>((i * sp.points + t) * np);
    final_row(P, st.shift[static_cast<std::size_t>(i)], u, st.S.data() + off, st.Sg.data() + off, part, vec, fil, T);
    score(P, i, part, ps[kPart]);
    score(P, i, vec, ps[kVector]);
    const auto oi = P.to_orig[static_cast<std::size_t>(i)];
    verification.row(oi) = chosen == kPart ? part : vec;
    filtration.row(oi) = fil;
  }
  for (int m : {kPart, kVector}) fig[m] = finish({ps[m]}, n, k);
}

// One full pass at α giving part-out and vector-out figures and the chosen mode's verification
// and the filtration outputs (caller's row order): one exp per pair. O(N²·D + N²).
void final_pass(const Prepared& P, double alpha, int chosen, Index block_rows, Figures fig[2], MatrixXd& verification,
                MatrixXd& filtration) {
  const Index n = P.X.rows(), k = P.Y.cols(), np = P.patterns.rows();
  const Index nb = (n + block_rows - 1) / block_rows;
  std::vector<PartialSums> parts[2];
  for (auto& p : parts) p.assign(static_cast<std::size_t>(nb), {});
  const double u = 1.0 / alpha;
  detail::for_each_d2_block(P.X, P.sq, P.X, P.sq, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
    RowState s;
    ArrayXd e;
    Eigen::RowVectorXd part(k), vec(k), fil(k);
    std::vector<double> S(static_cast<std::size_t>(np)), Sg(static_cast<std::size_t>(np)), T, sib;
    for (Index c = 0; c < rows; ++c) {
      const Index i = r0 + c;
      const auto oi = P.to_orig[static_cast<std::size_t>(i)];
      load_row(P, D2.col(c).data(), i, s);
      exp_floored(s.delta, u, e);
      run_sums(P, e, S.data());
      sibling_sums(s, u, Sg.data(), np, sib);
      final_row(P, shifts_of(s), u, S.data(), Sg.data(), part, vec, fil, T);
      score(P, i, part, parts[kPart][static_cast<std::size_t>(b)]);
      score(P, i, vec, parts[kVector][static_cast<std::size_t>(b)]);
      verification.row(oi) = chosen == kPart ? part : vec;
      filtration.row(oi) = fil;
    }
  });
  fig[kPart] = finish(parts[kPart], n, k);
  fig[kVector] = finish(parts[kVector], n, k);
}

// Median nonzero d² over all pairs (N(N−1)/2 ≤ 65,536) or 65,536 pairs from a fixed splitmix64
// sequence. O(pairs·D).
double d2_scale(const detail::RowMatrixXd& X) {  // row-major: one vector per contiguous row
  const Index n = X.rows();
  std::vector<double> v;
  const std::uint64_t all = static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n - 1) / 2;
  constexpr std::uint64_t kMaxPairs = 65536;
  if (all <= kMaxPairs) {
    for (Index i = 0; i < n; ++i)
      for (Index j = i + 1; j < n; ++j) v.push_back((X.row(i) - X.row(j)).squaredNorm());
  } else {
    std::uint64_t state = 0x6d696c6c6e6574ULL;  // fixed seed: "millnet"
    auto next = [&state]() {
      std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      return z ^ (z >> 31);
    };
    const auto un = static_cast<std::uint64_t>(n);
    for (std::uint64_t t = 0; t < kMaxPairs; ++t) {
      const auto i = static_cast<Index>(next() % un);
      auto j = static_cast<Index>(next() % (un - 1));
      if (j >= i) ++j;
      v.push_back((X.row(i) - X.row(j)).squaredNorm());
    }
  }
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !(x > 0.0); }), v.end());
  if (v.empty()) return 1.0;  // every vector identical: any α gives the same answer
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

struct Golden {
  double alpha = 0;
  Figures fig;
  int evaluations = 0;
};

// Golden section on u = ln α over [lo, hi] (α values); returns the best point evaluated, seeded
// with (alpha0, f0) so that the refinement never ends worse than the scan. Ties keep the
// smaller α. At most 200 evaluations.
template <class F>
Golden golden_section(F&& f, double lo, double hi, double alpha0, Figures f0, double tol_ln) {
  Golden best{alpha0, f0, 0};
  auto eval = [&](double u) {
    const double alpha = std::exp(u);
    const Figures fig = f(alpha);
    ++best.evaluations;
    if (fig.rms < best.fig.rms || (fig.rms == best.fig.rms && alpha < best.alpha)) {
      best.alpha = alpha;
      best.fig = fig;
    }
    return fig.rms;
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = std::log(lo), b = std::log(hi);
  if (!(b - a > tol_ln)) return best;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = eval(c), fd = eval(d);
  while (b - a > tol_ln && best.evaluations < 200) {
    if (fc <= fd) {
      b = d; d = c; fd = fc;
      c = b - g * (b - a); fc = eval(c);
    } else {
      a = c; c = d; fc = fd;
      d = a + g * (b - a); fd = eval(d);
    }
  }
  return best;
}


// ---- select_alpha, pass by pass ----------------------------------------------------------------
// The passes of the header comment, each a member of AlphaSearch (the state they share):
//   pre-scan   predict_grids       every k-th vector: which refinement grids the scan can evaluate
//   pass 1     scan_pass           all candidates of both modes, the predicted grids, the cache
//   pass 2     refine              per mode: golden section on the cache, else a grid
//   pass 3     outputs_at_alpha    verification and filtration at the chosen α

// Parameter checks that need no data. Throws millnet::Error.
void check_params(const AlphaSearchParams& prm) {
  if (prm.steps_per_octave < 1 || prm.steps_per_octave > 8)
    throw Error("alpha search: steps_per_octave must be in 1…8, got " + std::to_string(prm.steps_per_octave));
  if (prm.block_rows < 1) throw Error("alpha search: block_rows must be ≥ 1");
  if (prm.cache_neighbours < 1) throw Error("alpha search: cache_neighbours must be ≥ 1");
  if (!(prm.refine_tolerance_octaves > 0)) throw Error("alpha search: refine_tolerance_octaves must be > 0");
}

// The scan candidates, descending: α_k = hi · 2^(−r/q) · 2^(−m), k = r + q·m over the range
// [lo, hi] (relative to the d² scale unless alpha_min/alpha_max are given). ldexp halves exactly,
// which the squaring chains need.
std::vector<double> scan_candidates(const AlphaSearchParams& prm, double d2_scale) {
  double hi = prm.range_high * d2_scale, lo = prm.range_low * d2_scale;
  if (prm.alpha_min > 0 || prm.alpha_max > 0) {
    if (!(prm.alpha_min > 0 && prm.alpha_max > prm.alpha_min))
      throw Error("alpha search: alpha_min/alpha_max must both be > 0 with alpha_min < alpha_max");
    lo = prm.alpha_min;
    hi = prm.alpha_max;
  } else if (!(prm.range_low > 0 && prm.range_high > prm.range_low)) {
    throw Error("alpha search: range_low/range_high must both be > 0 with range_low < range_high");
  }
  const int q = prm.steps_per_octave;
  const auto nc = static_cast<Index>(std::floor(q * std::log2(hi / lo) + 1e-9)) + 1;
  if (nc < 2) throw Error("alpha search: the α range is narrower than one scan step");
  std::vector<double> alphas(static_cast<std::size_t>(nc));
  for (Index k = 0; k < nc; ++k)
    alphas[static_cast<std::size_t>(k)] =
        std::ldexp(hi * std::exp2(-static_cast<double>(k % q) / q), -static_cast<int>(k / q));
  return alphas;
}

// Per-thread buffers of the scan kernel.
struct ScanBuffers {
  ArrayXd e;
  std::vector<double> Sng, tmp, sib;
  std::vector<Lane> acc;
};

// Scan sums per block: 2·C entries per block (part-out candidates, then vector-out).
using ScanParts = std::vector<std::vector<PartialSums>>;

// Refinement grids of one pass (the scan's when the pre-scan predicted them, else their own) with
// the kept sums and the figures per point.
struct Grids {
  std::vector<GridSpec> specs;
  std::vector<GridStore> stores;
  GridParts parts;  // per-block sums while they are evaluated during the scan
  std::vector<std::vector<Figures>> figures;
};

// A grid whose results count for a mode's optimum.
struct GridResult {
  const GridSpec* spec = nullptr;
  const std::vector<Figures>* figures = nullptr;
  GridStore* store = nullptr;
};

// The chosen mode's optimum as a point of a grid (spec == nullptr: not on a grid).
struct GridPoint {
  const GridSpec* spec = nullptr;
  const GridStore* store = nullptr;
  Index point = 0;
};

class AlphaSearch {
 public:
  AlphaSearch(const Prepared& prepared, const AlphaSearchParams& params, std::vector<double> candidates)
      : P(prepared),
        prm(params),
        n(P.X.rows()),
        n_outputs(P.Y.cols()),
        n_patterns(P.patterns.rows()),
        block_rows(prm.block_rows),
        n_blocks((n + block_rows - 1) / block_rows),
        neighbours(std::min(prm.cache_neighbours, n)),
        alphas(std::move(candidates)),
        n_candidates(static_cast<Index>(this->alphas.size())),
        per_octave(prm.steps_per_octave),
        same_modes(P.singleton_groups),
        chosen(prm.mode == LooMode::PartOut ? kPart : kVector),
        tol_ln(prm.refine_tolerance_octaves * std::log(2.0)),
        margin_refine(tol::kRefineTruncationMargin + std::log(static_cast<double>(n))),
        // keeping the chosen mode's grid sums costs N·points·2P doubles: only within 2·N·(D + R)
        store_budget(std::max(static_cast<double>(n) * static_cast<double>(P.X.cols() + neighbours) * 2.0, 1e6)) {
    inv_alphas.resize(this->alphas.size());
    for (std::size_t k = 0; k < inv_alphas.size(); ++k) inv_alphas[k] = 1.0 / this->alphas[k];
    cache.dplus.assign(static_cast<std::size_t>(n), kInf);
    for (auto& m : cache.m) m.assign(static_cast<std::size_t>(n), 0.0);
  }

  // Fills rep (mode and d2_scale set by the caller): the table of contents of the search.
  void run(LooReport& rep) {
    Grids predicted = predict_grids();
    const ScanParts scan = scan_pass(predicted);
    if (prm.progress) prm.progress(1, 2);
    std::vector<Figures> scan_figures[2];
    scan_curve(scan, scan_figures, rep);
    Grids own_pass;  // grids the pre-scan did not predict
    const GridPoint chosen_point = refine(scan_figures, predicted, own_pass, rep);
    outputs_at_alpha(chosen_point, rep);
    rep.nearest_d2.resize(n);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) rep.nearest_d2(P.to_orig[i]) = cache.m[kPart][i];
    rep.full_passes = full_passes;
    rep.neighbour_cache_used = full_passes == 1;
    if (prm.progress) prm.progress(2, 2);
  }

 private:
  // ---- pre-scan: every k-th vector as a query against all N (1/k of a pass) predicts each
  // mode's best candidate, so that the scan pass can evaluate the refinement grid too; if the
  // full scan disagrees, the grid takes its own pass as before.
  Grids predict_grids() const {
    Grids g;
    const Index stride = prm.prescan_stride;
    if (stride >= 2 && n / stride >= 16) g.specs = prescan(stride);
    g.stores = make_stores(g.specs);
    g.parts = make_grid_parts(g.specs, n_blocks);
    return g;
  }

  std::vector<GridSpec> prescan(Index stride) const {
    const auto nc = static_cast<std::size_t>(n_candidates);
    std::vector<Index> rows_idx;
    for (Index i = 0; i < n; i += stride) rows_idx.push_back(i);
    const auto m = static_cast<Index>(rows_idx.size());
    detail::RowMatrixXd Q(m, P.X.cols());
    VectorXd sqQ(m);
    for (Index t = 0; t < m; ++t) {
      Q.row(t) = P.X.row(rows_idx[static_cast<std::size_t>(t)]);
      sqQ(t) = P.sq(rows_idx[static_cast<std::size_t>(t)]);
    }
    const Index nbq = (m + block_rows - 1) / block_rows;
    ScanParts pre(static_cast<std::size_t>(nbq), std::vector<PartialSums>(2 * nc));
    // each pre-scanned row's neighbour-cache gap per mode (first dropped d² − row minimum)
    std::vector<double> pre_gap[2];
    for (auto& g : pre_gap) g.assign(static_cast<std::size_t>(m), kInf);
    detail::for_each_d2_block(P.X, P.sq, Q, sqQ, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
      RowState s;
      ScanBuffers B;
      detail::NearestBuffers sel;
      Eigen::RowVectorXd out(n_outputs);
      for (Index c = 0; c < rows; ++c) {
        const Index i = rows_idx[static_cast<std::size_t>(r0 + c)];
        load_row(P, D2.col(c).data(), i, s);
        scan_row(s, i, pre[static_cast<std::size_t>(b)].data(), B, out);
        const double dplus = detail::nearest_cut(D2.col(c).data(), n, neighbours, sel);
        pre_gap[kPart][static_cast<std::size_t>(r0 + c)] = dplus - s.mp;
        pre_gap[kVector][static_cast<std::size_t>(r0 + c)] = dplus - s.mv;
      }
    });
    std::vector<GridSpec> specs;
    for (int mode : {kPart, kVector}) {
      if (mode == kVector && same_modes) continue;
      std::vector<Figures> f(nc);
      for (std::size_t k = 0; k < nc; ++k)
        f[k] = finish_slot(pre, static_cast<std::size_t>(mode) * nc + k, m, n_outputs);
      const Index best = best_candidate(f);
      // The refinement will run on the cache if it covers the bracket for every row: skip the
      // grid when the pre-scanned rows say it will, with a factor 2 to spare for the rows not
      // pre-scanned (if it does not, the grid takes its own pass; results are identical).
      const double est_covered =
          *std::min_element(pre_gap[mode].begin(), pre_gap[mode].end()) / margin_refine;
      if (alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))] <= 0.5 * est_covered) continue;
      bracket_grid(mode, best, specs);
    }
    return specs;
  }

  // ---- pass 1: scan + cache: every candidate of both modes, the predicted grids, and the R
  // nearest d² of every vector; then the range of α where the cache is exact.
  ScanParts scan_pass(Grids& predicted) {
    const auto un = static_cast<std::size_t>(n);
    ScanParts scan(static_cast<std::size_t>(n_blocks), std::vector<PartialSums>(2 * static_cast<std::size_t>(n_candidates)));
    std::vector<std::vector<double>> block_d2(static_cast<std::size_t>(n_blocks));
    std::vector<std::vector<std::int32_t>> block_j(static_cast<std::size_t>(n_blocks));
    std::vector<Index> row_length(un);
    detail::for_each_d2_block(P.X, P.sq, P.X, P.sq, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
      RowState s;
      ScanBuffers B;
      GridBuffers GB;
      detail::NearestBuffers sel;
      Eigen::RowVectorXd out(n_outputs);
      auto& sums = scan[static_cast<std::size_t>(b)];
      auto& cd = block_d2[static_cast<std::size_t>(b)];
      auto& cj = block_j[static_cast<std::size_t>(b)];
      for (Index c = 0; c < rows; ++c) {
        const Index i = r0 + c;
        const auto ui = static_cast<std::size_t>(i);
        const auto d = D2.col(c).array();
        const auto cd_before = static_cast<Index>(cd.size());
        load_row(P, D2.col(c).data(), i, s);
        cache.m[kPart][ui] = s.mp;
        cache.m[kVector][ui] = s.mv;
        cache.m[kFiltration][ui] = s.mf;  // load_row's minimum over the whole row
        scan_row(s, i, sums.data(), B, out);
        if (!predicted.specs.empty())
          grid_row(P, s, i, predicted.specs, predicted.stores, predicted.parts, b, GB, out);
        // R nearest (self and siblings included), in ascending j: expected O(N).
        const double dplus = detail::nearest_cut(D2.col(c).data(), n, neighbours, sel);
        cache.dplus[ui] = dplus;
        for (std::int32_t j : sel.idx)
          if (d(j) < dplus) {
            cd.push_back(d(j));
            cj.push_back(j);
          }
        row_length[ui] = static_cast<Index>(cd.size()) - cd_before;
      }
    });
    assemble_cache(row_length, block_d2, block_j);
    return scan;
  }

  // The cache in block order (CSR), and per mode the α up to which it is exact.
  void assemble_cache(const std::vector<Index>& row_length, std::vector<std::vector<double>>& block_d2,
                      std::vector<std::vector<std::int32_t>>& block_j) {
    const auto un = static_cast<std::size_t>(n);
    cache.offset.assign(un + 1, 0);
    for (std::size_t i = 0; i < un; ++i) cache.offset[i + 1] = cache.offset[i] + row_length[i];
    cache.d2.reserve(static_cast<std::size_t>(cache.offset[un]));
    cache.j.reserve(static_cast<std::size_t>(cache.offset[un]));
    for (std::size_t b = 0; b < block_d2.size(); ++b) {
      cache.d2.insert(cache.d2.end(), block_d2[b].begin(), block_d2[b].end());
      cache.j.insert(cache.j.end(), block_j[b].begin(), block_j[b].end());
      std::vector<double>().swap(block_d2[b]);
      std::vector<std::int32_t>().swap(block_j[b]);
    }
    const double margin = tol::kTruncationMargin + std::log(static_cast<double>(n));
    for (int mode : {kPart, kVector, kFiltration}) {
      double gap = kInf;  // smallest (first dropped d² − row minimum) over all rows
      for (std::size_t i = 0; i < un; ++i) gap = std::min(gap, cache.dplus[i] - cache.m[mode][i]);
      cache.covered[mode] = std::max(gap / margin, 0.0);
      cache.covered_refine[mode] = std::max(gap / margin_refine, 0.0);
    }
  }

  // Both modes' scan figures per candidate, and the scan curve (ascending α) into rep.
  void scan_curve(const ScanParts& scan, std::vector<Figures> fig[2], LooReport& rep) const {
    const auto nc = static_cast<std::size_t>(n_candidates);
    for (int mode : {kPart, kVector}) {
      fig[mode].resize(nc);
      for (std::size_t k = 0; k < nc; ++k)
        fig[mode][k] = finish_slot(scan, static_cast<std::size_t>(mode) * nc + k, n, n_outputs);
    }
    if (same_modes) fig[kVector] = fig[kPart];
    for (Index k = n_candidates - 1; k >= 0; --k) {
      const auto uk = static_cast<std::size_t>(k);
      rep.curve.push_back({alphas[uk], fig[kPart][uk].rms, fig[kVector][uk].rms, fig[kPart][uk].accuracy,
                           fig[kVector][uk].accuracy});
    }
  }

  // ---- pass 2: refinement per mode ----------------------------------------------------------
  // Golden section on the cache when it is exact (looser refinement margin) over the mode's whole
  // bracket; otherwise the grid evaluated during the scan when the pre-scan predicted this
  // bracket, else ONE full pass for every remaining mode together. Returns the chosen mode's
  // optimum when it lies on a grid.
  GridPoint refine(const std::vector<Figures> scan_figures[2], Grids& predicted, Grids& own_pass, LooReport& rep) {
    std::vector<GridResult> grids;  // every grid whose results count
    predicted.figures = grid_results(predicted.parts, predicted.specs, n, n_outputs);
    for (int mode : {kPart, kVector}) {
      const Index best = best_candidate(scan_figures[mode]);
      ModeOptimum& opt = mode == kPart ? rep.part : rep.vector;
      opt.edge = best == 0 ? Edge::High : best == n_candidates - 1 ? Edge::Low : Edge::None;
      if (mode == kVector && same_modes) continue;
      if (refine_on_cache(mode, best, opt)) continue;
      std::vector<GridSpec> want;
      bracket_grid(mode, best, want);
      std::vector<std::size_t> match;
      if (was_predicted(predicted.specs, mode, want, match)) {
        for (std::size_t g : match)
          grids.push_back({&predicted.specs[g], &predicted.figures[g], &predicted.stores[g]});
      } else {
        own_pass.specs.insert(own_pass.specs.end(), want.begin(), want.end());
      }
    }
    own_pass.stores = make_stores(own_pass.specs);
    if (!own_pass.specs.empty()) {
      ++full_passes;
      own_pass.figures = grid_pass(P, own_pass.specs, block_rows, own_pass.stores);
      for (std::size_t g = 0; g < own_pass.specs.size(); ++g)
        grids.push_back({&own_pass.specs[g], &own_pass.figures[g], &own_pass.stores[g]});
    }
    const GridPoint point = grid_optima(grids, rep);
    if (same_modes) {
      const Edge e = rep.vector.edge;
      rep.vector = rep.part;
      rep.vector.edge = e;
    }
    return point;
  }

  // Golden section on the cache around candidate `best` when the cache is exact over the whole
  // bracket; false (opt untouched) otherwise.
  bool refine_on_cache(int mode, Index best, ModeOptimum& opt) {
    const double a_hi = alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))];
    const double a_lo = alphas[static_cast<std::size_t>(std::min<Index>(best + 1, n_candidates - 1))];
    const double a0 = alphas[static_cast<std::size_t>(best)];
    if (!(a_hi <= cache.covered_refine[mode])) return false;
    const Evaluator ev{P, cache, block_rows, &full_passes, true};
    const Figures f0 = ev(a0, mode);
    const Golden g = golden_section([&](double a) { return ev(a, mode); }, a_lo, a_hi, a0, f0, tol_ln);
    opt.alpha = g.alpha;
    opt.rms = g.fig.rms;
    opt.accuracy = g.fig.accuracy;
    opt.refine_evaluations = g.evaluations + 1;
    return true;
  }

  // Whether the pre-scan predicted exactly the grids `want` of the mode; their indices in match.
  static bool was_predicted(const std::vector<GridSpec>& predicted, int mode, const std::vector<GridSpec>& want,
                            std::vector<std::size_t>& match) {
    for (std::size_t g = 0; g < predicted.size(); ++g)
      if (predicted[g].mode == mode) match.push_back(g);
    bool same = match.size() == want.size();
    for (std::size_t t = 0; same && t < want.size(); ++t) {
      const GridSpec& a = predicted[match[t]];
      same = a.u0 == want[t].u0 && a.h == want[t].h && a.points == want[t].points;
    }
    return same;
  }

  // Each mode's optimum over its grid points (ties → smaller α) into rep; the chosen mode's as a
  // grid point.
  GridPoint grid_optima(const std::vector<GridResult>& grids, LooReport& rep) const {
    GridPoint chosen_point;
    for (int mode : {kPart, kVector}) {
      ModeOptimum& opt = mode == kPart ? rep.part : rep.vector;
      bool first = true;
      for (const GridResult& g : grids) {
        const GridSpec& sp = *g.spec;
        if (sp.mode != mode) continue;
        for (Index t = 0; t < sp.points; ++t) {
          const double a = 1.0 / (sp.u0 + static_cast<double>(t) * sp.h);
          const Figures& f = (*g.figures)[static_cast<std::size_t>(t)];
          if (first || f.rms < opt.rms || (f.rms == opt.rms && a < opt.alpha)) {
            first = false;
            opt.alpha = a;
            opt.rms = f.rms;
            opt.accuracy = f.accuracy;
            if (mode == chosen) chosen_point = {&sp, g.store, t};
          }
        }
        opt.refine_evaluations += static_cast<int>(sp.points);
      }
    }
    return chosen_point;
  }

  // ---- pass 3: outputs at the chosen α: from the grid sums kept for it, else from the cache
  // when it is exact for every mode, else one full pass for both modes and the filtration.
  void outputs_at_alpha(const GridPoint& on_grid, LooReport& rep) {
    rep.alpha = chosen == kPart ? rep.part.alpha : rep.vector.alpha;
    rep.verification.resize(n, n_outputs);
    rep.filtration.resize(n, n_outputs);
    Figures fm[2];
    if (on_grid.spec && !on_grid.store->S.empty()) {  // no further pass
      outputs_from_store(P, *on_grid.spec, *on_grid.store, on_grid.point, chosen, fm, rep.verification,
                         rep.filtration);
    } else if (rep.alpha <= std::min({cache.covered[kPart], cache.covered[kVector], cache.covered[kFiltration]})) {
      const Evaluator ev{P, cache, block_rows, &full_passes, false};
      fm[chosen] = ev(rep.alpha, chosen, &rep.verification);
      fm[1 - chosen] = ev(rep.alpha, 1 - chosen);
      (void)ev(rep.alpha, kFiltration, &rep.filtration);
    } else {  // one pass for both modes and the filtration
      ++full_passes;
      final_pass(P, rep.alpha, chosen, block_rows, fm, rep.verification, rep.filtration);
    }
    rep.rms_part_at_alpha = fm[kPart].rms;
    rep.rms_vector_at_alpha = fm[kVector].rms;
    rep.accuracy_part_at_alpha = fm[kPart].accuracy;
    rep.accuracy_vector_at_alpha = fm[kVector].accuracy;
    // the chosen mode's optimum is reported with the exact figures at its α
    ModeOptimum& copt = chosen == kPart ? rep.part : rep.vector;
    copt.rms = fm[chosen].rms;
    copt.accuracy = fm[chosen].accuracy;
    if (same_modes) {
      ModeOptimum& other = chosen == kPart ? rep.vector : rep.part;
      other.rms = copt.rms;
      other.accuracy = copt.accuracy;
    }
  }

  // ---- shared steps ----------------------------------------------------------------------------

  // Scan of one loaded row into sums (2·C entries: part-out, then vector-out): other-group sums
  // at every candidate from q squaring chains α, α/2, α/4, … (one exp per pair per chain, then a
  // square and an add per pair and candidate): O(N·(q + C)).
  void scan_row(const RowState& s, Index i, PartialSums* sums, ScanBuffers& B, Eigen::RowVectorXd& out) const {
    const Index nc = n_candidates, q = per_octave, np = n_patterns;
    B.Sng.resize(static_cast<std::size_t>(nc) * static_cast<std::size_t>(np));
    for (Index r = 0; r < std::min<Index>(q, nc); ++r) {
      exp_floored(s.delta, inv_alphas[static_cast<std::size_t>(r)], B.e);
      const Index steps = (nc - r + q - 1) / q;  // candidates r, r + q, r + 2q, …
      for (Index p = 0; p < np; ++p)
        power_sums<true>(B.e.data(), nullptr, P.pstart[static_cast<std::size_t>(p)],
                         P.pstart[static_cast<std::size_t>(p) + 1], steps, B.Sng.data() + r * np + p, q * np, B.acc);
    }
    score_modes(P, s, i, inv_alphas.data(), nc, B.Sng.data(), sums,
                same_modes ? nullptr : sums + static_cast<std::size_t>(nc), out, B.tmp, B.sib);
  }

  // The candidate with the smallest RMS; ties → smaller α.
  Index best_candidate(const std::vector<Figures>& f) const {
    Index best = 0;
    for (Index k = 1; k < n_candidates; ++k)
      if (f[static_cast<std::size_t>(k)].rms <= f[static_cast<std::size_t>(best)].rms) best = k;
    return best;
  }

  // One grid over the bracket [α_lo, α_hi] around candidate `best`, points even in 1/α with ONE
  // step h (so each pair costs 2 exps, e at the first point and the ratio r = exp(−δ·h), then a
  // multiply per point): h is the finer of the two halves' steps, each half [α_hi, α_best] and
  // [α_best, α_lo] having width / tolerance steps, at most kMaxSteps; α_best is a grid point
  // and the grid ends at or just past α_lo.
  void bracket_grid(int mode, Index best, std::vector<GridSpec>& out_specs) const {
    constexpr double kMaxSteps = 16;
    const double a_hi = alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))];
    const double a_lo = alphas[static_cast<std::size_t>(std::min<Index>(best + 1, n_candidates - 1))];
    const double a0 = alphas[static_cast<std::size_t>(best)];
    double h = kInf;
    for (const auto& [a_top, a_bot] : {std::pair{a_hi, a0}, std::pair{a0, a_lo}}) {
      if (!(a_top > a_bot)) continue;
      const double steps = std::clamp(std::ceil(std::log(a_top / a_bot) / tol_ln), 1.0, kMaxSteps);
      h = std::min(h, (1.0 / a_bot - 1.0 / a_top) / steps);
    }
    if (!(h < kInf)) return;
    const double above = a_hi > a0 ? std::round((1.0 / a0 - 1.0 / a_hi) / h) : 0.0;
    const double below = a0 > a_lo ? std::ceil((1.0 / a_lo - 1.0 / a0) / h - 1e-9) : 0.0;
    GridSpec sp;
    sp.mode = mode;
    sp.h = h;
    sp.u0 = 1.0 / a0 - above * h;
    sp.points = static_cast<Index>(above + below) + 1;
    out_specs.push_back(sp);
  }

  // Stores for the chosen mode's grids when their sums fit the budget (else left empty).
  std::vector<GridStore> make_stores(const std::vector<GridSpec>& specs) const {
    std::vector<GridStore> st(specs.size());
    double need = 0;
    for (const auto& g : specs)
      if (g.mode == chosen) need += static_cast<double>(n) * static_cast<double>(g.points * n_patterns) * 2.0;
    for (std::size_t g = 0; g < specs.size(); ++g)
      if (specs[g].mode == chosen && need <= store_budget) {
        const auto sz = static_cast<std::size_t>(n * specs[g].points * n_patterns);
        st[g].S.assign(sz, 0.0);
        st[g].Sg.assign(sz, 0.0);
        st[g].shift.resize(static_cast<std::size_t>(n));
      }
    return st;
  }

  const Prepared& P;
  const AlphaSearchParams& prm;
  const Index n;           // stored vectors N
  const Index n_outputs;   // K
  const Index n_patterns;  // distinct output rows P
  const Index block_rows, n_blocks;
  const Index neighbours;  // R: nearest d² kept per vector
  const std::vector<double> alphas;  // scan candidates, descending
  std::vector<double> inv_alphas;
  const Index n_candidates;  // C
  const Index per_octave;    // q: candidates per octave (= squaring chains)
  const bool same_modes;     // one vector per group: part-out = vector-out
  const int chosen;          // the mode that chooses α
  const double tol_ln;         // refinement tolerance in ln α
  const double margin_refine;  // truncation margin of the refinement on the cache
  const double store_budget;   // doubles the chosen mode's grid sums may take
  Cache cache;
  int full_passes = 1;  // the scan
};

}  // namespace

namespace detail {

Prepared prepare(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups) {
  const Index n = Xn.rows();
  if (n < 2) throw Error("classifier: need at least 2 stored vectors, got " + std::to_string(n));
  if (Xn.cols() < 1) throw Error("classifier: inputs have no columns (expected N×D, D ≥ 1)");
  if (Y.rows() != n || Y.cols() < 1)
    throw Error("classifier: outputs are " + std::to_string(Y.rows()) + "×" + std::to_string(Y.cols()) +
                ", expected " + std::to_string(n) + "×K with K ≥ 1 (one row per input vector)");
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
    for (Index i = P.pstart[p]; i < P.pstart[p + 1]; ++i) P.pattern[static_cast<std::size_t>(i)] = static_cast<Index>(p);
  return P;
}

}  // namespace detail

const char* to_string(LooMode m) { return m == LooMode::PartOut ? "part" : "vector"; }

LooMode loo_mode_from_string(const std::string& s) {
  if (s == "part") return LooMode::PartOut;
  if (s == "vector") return LooMode::VectorOut;
  throw Error("leave-one-out mode: got \"" + s + "\", expected \"part\" or \"vector\"");
}

const char* to_string(Edge e) { return e == Edge::None ? "none" : e == Edge::Low ? "low" : "high"; }

double rms_error(const MatrixXd& outputs, const MatrixXd& Y) {
  if (outputs.rows() != Y.rows() || outputs.cols() != Y.cols() || Y.size() == 0)
    throw Error("rms_error: outputs and targets differ in shape or are empty");
  return std::sqrt((outputs - Y).squaredNorm() / static_cast<double>(Y.size()));
}

double argmax_accuracy(const MatrixXd& outputs, const MatrixXd& Y) {
  if (outputs.rows() != Y.rows() || outputs.cols() != Y.cols() || Y.rows() == 0)
    throw Error("argmax_accuracy: outputs and targets differ in shape or are empty");
  Index ok = 0;
  for (Index i = 0; i < Y.rows(); ++i) ok += detail::argmax(outputs.row(i)) == detail::argmax(Y.row(i)) ? 1 : 0;
  return static_cast<double>(ok) / static_cast<double>(Y.rows());
}

MatrixXd verification_outputs(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups,
                              double alpha, LooMode mode, Index block_rows) {
  if (!(alpha > 0) || !std::isfinite(alpha)) throw Error("verification_outputs: alpha must be finite and > 0");
  if (block_rows < 1) throw Error("verification_outputs: block_rows must be ≥ 1");
  const Prepared P = detail::prepare(Xn, Y, groups);
  if (mode == LooMode::PartOut && P.members.size() < 2)
    throw Error("leave-one-part-out needs at least 2 groups (source parts)");
  MatrixXd out(Xn.rows(), Y.cols());
  (void)full_pass(P, alpha, mode == LooMode::PartOut ? kPart : kVector, block_rows, &out);
  return out;
}

LooReport select_alpha(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups,
                       const AlphaSearchParams& prm) {
  check_params(prm);
  const Prepared P = detail::prepare(Xn, Y, groups);
  if (P.members.size() < 2)
    throw Error("leave-one-out: the stored vectors come from a single group (source part); both figures "
                "(part-out and vector-out) need at least 2 groups");
  LooReport rep;
  rep.mode = prm.mode;
  rep.d2_scale = d2_scale(P.X);
  AlphaSearch(P, prm, scan_candidates(prm, rep.d2_scale)).run(rep);
  return rep;
}

}  // namespace millnet::classifier
