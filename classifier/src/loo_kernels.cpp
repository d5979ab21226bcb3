// Kernels of the leave-one-out α search: see loo_kernels.hpp.
#include "loo_kernels.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::classifier::detail::loo {

namespace {

// Sets the excluded entries of stored-vector i's d² row to +inf for the mode. O(group size).
void mask(const Prepared& P, Index i, int mode, ArrayXd& w) {
  if (mode == kPart) {
    for (Index j : P.members[static_cast<std::size_t>(P.group[static_cast<std::size_t>(i)])]) w(j) = kInf;
  } else if (mode == kVector) {
    w(i) = kInf;
  }
}

Figures finish(const std::vector<PartialSums>& blocks, Index n, Index k) {
  double err = 0;
  Index correct = 0;
  for (const auto& b : blocks) {  // block order: identical for any thread count
    err += b.err;
    correct += b.correct;
  }
  return {std::sqrt(err / static_cast<double>(n * k)), static_cast<double>(correct) / static_cast<double>(n)};
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

// Scores row i's prediction `out` into ps.
void score(const Prepared& P, Index i, const Eigen::RowVectorXd& out, PartialSums& ps) {
  ps.err += (out - P.Y.row(i)).squaredNorm();
  ps.correct += detail::argmax(out) == P.label[static_cast<std::size_t>(i)] ? 1 : 0;
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

// Part-out, vector-out and filtration outputs of row i at inverse width u from its other-group
// run sums S (shift m_p) and sibling run sums Sg (shift m_v). O(P·K).
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

}  // namespace

Figures finish_slot(const std::vector<std::vector<PartialSums>>& blocks, std::size_t slot, Index n, Index k) {
  std::vector<PartialSums> col(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) col[b] = blocks[b][slot];
  return finish(col, n, k);
}

void exp_floored(const ArrayXd& delta, double u, ArrayXd& e) {
  e.resize(delta.size());
  detail::exp_neg_scaled(delta.data(), u, tol::kSimilarityFloor, e.data(), delta.size());
}

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

Figures cache_pass(const Prepared& P, const Cache& C, double alpha, int mode, Index block_rows, MatrixXd* outputs) {
  const Index n = P.X.rows(), k = P.Y.cols();
  const Index nb = (n + block_rows - 1) / block_rows;
  std::vector<PartialSums> parts(static_cast<std::size_t>(nb));
  const double inv_alpha = 1.0 / alpha;
#pragma omp parallel for schedule(dynamic, 1) if (static_cast <double>(C.d2.size()) > detail::kParallelWork)
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

GridParts make_grid_parts(const std::vector<GridSpec>& specs, Index nb) {
  GridParts parts(specs.size(), std::vector<std::vector<PartialSums>>(static_cast<std::size_t>(nb)));
  for (std::size_t g = 0; g < specs.size(); ++g)
    for (auto& v : parts[g]) v.assign(static_cast<std::size_t>(specs[g].points), {});
  return parts;
}

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

std::vector<std::vector<Figures>> grid_results(const GridParts& parts, const std::vector<GridSpec>& specs, Index n,
                                               Index k) {
  std::vector<std::vector<Figures>> res(specs.size());
  for (std::size_t g = 0; g < specs.size(); ++g)
    for (Index t = 0; t < specs[g].points; ++t)
      res[g].push_back(finish_slot(parts[g], static_cast<std::size_t>(t), n, k));
  return res;
}

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

}  // namespace millnet::classifier::detail::loo
