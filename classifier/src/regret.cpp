// Judging a network by the regret of its picks (regret.hpp).
#include "millnet/classifier/regret.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "engine.hpp"
#include "simd.hpp"
#include "millnet/classifier/tolerances.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::RowVectorXd;
using Eigen::VectorXd;

namespace {

/// Ranks (1-based) with ties given their mean rank. O(n log n).
std::vector<double> mean_ranks(const std::vector<double>& v) {
  std::vector<std::size_t> ord(v.size());
  std::iota(ord.begin(), ord.end(), std::size_t{0});
  std::stable_sort(ord.begin(), ord.end(), [&](std::size_t a, std::size_t b) { return v[a] > v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < ord.size();) {
    std::size_t j = i;
    while (j + 1 < ord.size() && v[ord[j + 1]] == v[ord[i]]) ++j;
    for (std::size_t t = i; t <= j; ++t) r[ord[t]] = 0.5 * static_cast<double>(i + j) + 1;
    i = j + 1;
  }
  return r;
}

/// Spearman's ρ with mean ranks for ties (Pearson's r of the ranks); NaN when either is constant.
double spearman_ties(const std::vector<double>& a, const std::vector<double>& b) {
  const std::vector<double> ra = mean_ranks(a), rb = mean_ranks(b);
  const double n = static_cast<double>(ra.size());
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n, mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  if (!(saa > 0) || !(sbb > 0)) return std::numeric_limits<double>::quiet_NaN();
  return sab / std::sqrt(saa * sbb);
}

double nearest_rank(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(k, 1, v.size()) - 1];
}

/// Pool-adjacent-violators: the non-decreasing step function of y on x (each point weight 1;
/// equal x pooled first), each block's mean smoothed as below. Blocks' upper x ascending.
void isotonic(std::vector<std::pair<double, double>> pts, std::vector<double>& raw, std::vector<double>& value) {
  std::sort(pts.begin(), pts.end());
  struct Block {
    double x_hi, sum, n;
  };
  std::vector<Block> b;
  for (std::size_t i = 0; i < pts.size();) {
    std::size_t j = i;
    Block blk{pts[i].first, 0, 0};
    for (; j < pts.size() && pts[j].first == pts[i].first; ++j) {
      blk.sum += pts[j].second;
      blk.n += 1;
    }
    b.push_back(blk);
    while (b.size() > 1 && b[b.size() - 2].sum / b[b.size() - 2].n >= b.back().sum / b.back().n) {
      const Block top = b.back();
      b.pop_back();
      b.back() = {top.x_hi, b.back().sum + top.sum, b.back().n + top.n};
    }
    i = j;
  }
  // Each block's share by the rule of succession, (right + 1) / (picks + 2): a block of 29 right
  // picks out of 29 says 0.97, not a certainty no 29 parts can show; kept non-decreasing.
  raw.clear();
  value.clear();
  for (const Block& k : b) {
    raw.push_back(k.x_hi);
    value.push_back(std::max(value.empty() ? 0.0 : value.back(), (k.sum + 1) / (k.n + 2)));
  }
}

}  // namespace

double pick_regret(const Eigen::Ref<const RowVectorXd>& y, Index k) {
  const double top = y.maxCoeff();
  if (!(top > 0)) return 0;  // every strategy scores 0 on the part: no pick is worse than another
  if (y(k) >= top) return 0;
  if (!(y(k) > 0)) return tol::kMissRegret;
  return top / y(k) - 1;
}

std::vector<PartPick> part_picks(const MatrixXd& predicted, const MatrixXd& Y, const std::vector<std::string>& groups,
                                 const VectorXd& d2_min) {
  const Index n = Y.rows(), K = Y.cols();
  if (predicted.rows() != n || predicted.cols() != K || static_cast<Index>(groups.size()) != n ||
      (d2_min.size() != 0 && d2_min.size() != n))
    throw Error("part_picks: predicted, outputs, groups and d2_min differ in length");
  std::map<std::string, std::size_t> id;
  std::vector<PartPick> picks;
  std::vector<double> count;
  std::vector<bool> active(static_cast<std::size_t>(K), false);
  for (Index i = 0; i < n; ++i)  // O(N·K)
    for (Index k = 0; k < K; ++k)
      if (Y(i, k) != 0) active[static_cast<std::size_t>(k)] = true;
  for (Index i = 0; i < n; ++i) {
    const auto [it, fresh] = id.try_emplace(groups[static_cast<std::size_t>(i)], picks.size());
    if (fresh) {
      PartPick p;
      p.part = groups[static_cast<std::size_t>(i)];
      p.predicted = RowVectorXd::Zero(K);
      p.outputs = Y.row(i);
      p.d2_min = std::numeric_limits<double>::infinity();
      picks.push_back(std::move(p));
      count.push_back(0);
    }
    PartPick& p = picks[it->second];
    if (p.outputs != Y.row(i))
      throw Error("part_picks: the vectors of part '" + p.part + "' carry different outputs (a part has one label)");
    p.predicted += predicted.row(i);
    count[it->second] += 1;
    if (d2_min.size() != 0) p.d2_min = std::min(p.d2_min, d2_min(i));
  }
  for (std::size_t g = 0; g < picks.size(); ++g) {
    PartPick& p = picks[g];
    p.predicted /= count[g];
    if (d2_min.size() == 0) p.d2_min = 0;
    p.best = detail::argmax(p.outputs);
    p.pick = detail::argmax(p.predicted);
    p.regret = pick_regret(p.outputs, p.pick);
    p.miss = !(p.outputs(p.pick) > 0) && p.outputs.maxCoeff() > 0;
    double second = -std::numeric_limits<double>::infinity();
    for (Index k = 0; k < K; ++k)
      if (k != p.pick) second = std::max(second, p.predicted(k));
    p.margin = K > 1 ? std::max(0.0, p.predicted(p.pick) - second) : 1.0;
    std::vector<double> a, b;
    for (Index k = 0; k < K; ++k)
      if (active[static_cast<std::size_t>(k)]) {
        a.push_back(p.predicted(k));
        b.push_back(p.outputs(k));
      }
    p.spearman = spearman_ties(a, b);
  }
  return picks;
}

bool one_output_per_part(const MatrixXd& Y, const std::vector<std::string>& groups) {
  std::map<std::string, Index> first;
  for (Index i = 0; i < Y.rows(); ++i) {
    const auto [it, fresh] = first.try_emplace(groups[static_cast<std::size_t>(i)], i);
    if (!fresh && Y.row(it->second) != Y.row(i)) return false;
  }
  return true;
}

RegretSummary summarize(const std::vector<PartPick>& picks) {
  RegretSummary s;
  s.parts = picks.size();
  if (picks.empty()) return s;
  std::vector<double> r;
  double rho = 0, rho_n = 0, right = 0;
  for (const PartPick& p : picks) {
    r.push_back(p.regret);
    right += p.regret == 0 ? 1 : 0;
    s.misses += p.miss ? 1 : 0;
    if (std::isfinite(p.spearman)) {
      rho += p.spearman;
      rho_n += 1;
    }
  }
  s.top1 = right / static_cast<double>(picks.size());
  s.mean = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
  s.median = nearest_rank(r, 0.5);
  s.p90 = nearest_rank(r, 0.9);
  if (rho_n > 0) s.spearman = rho / rho_n;
  return s;
}

Baseline always_the_same(const std::vector<PartPick>& picks) {
  Baseline b;
  if (picks.empty()) return b;
  const Index K = picks.front().outputs.size();
  std::vector<int> wins(static_cast<std::size_t>(K), 0);
  for (const PartPick& p : picks) ++wins[static_cast<std::size_t>(p.best)];
  b.slot = static_cast<Index>(std::max_element(wins.begin(), wins.end()) - wins.begin());
  std::vector<PartPick> same = picks;
  for (PartPick& p : same) {
    p.pick = b.slot;
    p.regret = pick_regret(p.outputs, b.slot);
    p.miss = !(p.outputs(b.slot) > 0) && p.outputs.maxCoeff() > 0;
    p.spearman = std::numeric_limits<double>::quiet_NaN();
  }
  b.figures = summarize(same);
  return b;
}

namespace {
/// The output rows as runs of consecutive vectors with one output row (a part's variants, stored
/// together): Σ_j w_j·Y_j = Σ_runs (Σ_{j ∈ run} w_j)·Y_run, a K × runs product instead of K × N —
/// the 8 × 11,000 output matrix streamed from memory once per vector and α was the weighted sums'
/// time (500 parts × 22 variants: 41 α × N² · 8 multiply-adds).
struct OutputRuns {
  std::vector<Index> start;  // runs + 1
  MatrixXd Yr;               // K × runs
  [[nodiscard]] Eigen::RowVectorXd weighted_mean(const Eigen::Ref<const VectorXd>& w) const {
    const auto runs = static_cast<Index>(start.size()) - 1;
    VectorXd wr(runs);
    for (Index r = 0; r < runs; ++r) {  // O(N)
      const auto b = start[static_cast<std::size_t>(r)], e = start[static_cast<std::size_t>(r) + 1];
      wr(r) = w.segment(b, e - b).sum();
    }
    return (Yr * wr).transpose() / wr.sum();
  }
};
/// The α in descending order and, per α, the α twice as large whose weights it squares (−1: an
/// exp of its own). The scan's candidates halve exactly every steps_per_octave (ldexp); a chain is
/// restarted from an exp every kMaxSquarings (each squaring doubles the relative error: ≤ 2⁴ ulp).
struct Halvings {
  std::vector<std::size_t> order;
  std::vector<std::ptrdiff_t> from;
};
Halvings halving_chains(const std::vector<double>& alphas) {
  constexpr int kMaxSquarings = 4;
  Halvings h;
  h.order.resize(alphas.size());
  std::iota(h.order.begin(), h.order.end(), std::size_t{0});
  std::stable_sort(h.order.begin(), h.order.end(), [&](std::size_t a, std::size_t b) { return alphas[a] > alphas[b]; });
  h.from.assign(alphas.size(), -1);
  std::vector<int> depth(alphas.size(), 0);
  for (std::size_t k = 0; k < h.order.size(); ++k) {  // O(|alphas|²), 41 here
    const std::size_t a = h.order[k];
    for (std::size_t m = 0; m < k; ++m) {
      const std::size_t b = h.order[m];
      if (alphas[b] == 2 * alphas[a] && depth[b] < kMaxSquarings) {
        h.from[a] = static_cast<std::ptrdiff_t>(b);
        depth[a] = depth[b] + 1;
        break;
      }
    }
  }
  return h;
}

OutputRuns output_runs(const MatrixXd& Y, const std::vector<int>& gid) {
  OutputRuns o;
  std::vector<Index> rep;
  for (Index j = 0; j < Y.rows(); ++j) {  // O(N·K)
    const bool same =
        j > 0 && gid[static_cast<std::size_t>(j)] == gid[static_cast<std::size_t>(j) - 1] && Y.row(j) == Y.row(j - 1);
    if (!same) {
      o.start.push_back(j);
      rep.push_back(j);
    }
  }
  o.start.push_back(Y.rows());
  o.Yr.resize(Y.cols(), static_cast<Index>(rep.size()));
  for (std::size_t r = 0; r < rep.size(); ++r) o.Yr.col(static_cast<Index>(r)) = Y.row(rep[r]).transpose();
  return o;
}
}  // namespace

std::vector<MatrixXd> part_out_outputs(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups,
                                       const std::vector<double>& alphas, Index block_rows) {
  const Index n = Xn.rows(), K = Y.cols();
  if (Y.rows() != n || static_cast<Index>(groups.size()) != n)
    throw Error("part_out_outputs: inputs, outputs and groups differ in length");
  for (double a : alphas)
    if (!(a > 0) || !std::isfinite(a)) throw Error("part_out_outputs: every alpha must be finite and > 0");
  std::map<std::string, int> ids;
  std::vector<int> gid(groups.size());
  for (std::size_t i = 0; i < gid.size(); ++i)
    gid[i] = ids.try_emplace(groups[i], static_cast<int>(ids.size())).first->second;
  if (ids.size() < 2) throw Error("part_out_outputs: leave-one-part-out needs at least 2 parts");
  std::vector<MatrixXd> out(alphas.size(), MatrixXd::Zero(n, K));
  const VectorXd sq = Xn.rowwise().squaredNorm();
  const OutputRuns runs = output_runs(Y, gid);
  const Halvings halvings = halving_chains(alphas);
  // Per left-out vector: δ_j = d²_j − d²_min over the other parts (+∞ on its own part: weight 0),
  // then per α the weights exp(−δ/α) in vector lanes (simd.hpp; below the similarity floor: 0)
  // and their weighted output sum. The 41 α × N² weights decide the time: in lanes, not one libm
  // exp a call (bench_classifier BM_TrainByRegret/500, 500 parts × 22 variants, the whole train on
  // 2 cores: 23.5 s with libm's exp, 9.1 s in lanes).
  detail::for_each_d2_block(Xn, sq, Xn, sq, block_rows, [&](Index, Index r0, Index rows, const MatrixXd& D2) {
    VectorXd delta(n);
    MatrixXd w(n, static_cast<Index>(alphas.size()));  // per α its weights, N × |alphas|
    for (Index c = 0; c < rows; ++c) {
      const Index i = r0 + c;
      const int g = gid[static_cast<std::size_t>(i)];
      double m = std::numeric_limits<double>::infinity();
      for (Index j = 0; j < n; ++j)  // O(N)
        if (gid[static_cast<std::size_t>(j)] != g) m = std::min(m, D2(j, c));
      for (Index j = 0; j < n; ++j)
        delta(j) = gid[static_cast<std::size_t>(j)] == g ? std::numeric_limits<double>::infinity() : D2(j, c) - m;
      for (const std::size_t a : halvings.order) {  // O(|alphas|·(N + runs·K)), larger α first
        const auto ca = static_cast<Index>(a);
        const std::ptrdiff_t from = halvings.from[a];
        if (from < 0) {
          detail::exp_neg_scaled(delta.data(), 1.0 / alphas[a], tol::kSimilarityFloor, w.col(ca).data(), n);
        } else {  // exp(−δ/α) = exp(−δ/(2α))²: one multiply instead of an exp
          const double* src = w.col(static_cast<Index>(from)).data();
          double* dst = w.col(ca).data();
          for (Index j = 0; j < n; ++j) {
            const double v = src[j] * src[j];
            dst[j] = v < tol::kSimilarityFloor ? 0.0 : v;
          }
        }
        out[a].row(i) = runs.weighted_mean(w.col(ca));
      }
    }
  });
  return out;
}

double Calibration::familiarity(double d2_min) const {
  if (!(threshold > 0)) return 1;
  if (!(d2_min > threshold)) return 1;
  return threshold / d2_min;
}

double Calibration::confidence(Index pick, double margin, double d2_min) const {
  const double f = familiarity(d2_min);
  const double prior_pick =
      pick >= 0 && static_cast<std::size_t>(pick) < prior.size() ? prior[static_cast<std::size_t>(pick)] : 0.0;
  if (raw.empty()) return (1 - f) * prior_pick;
  const double x = margin * f;
  const auto it = std::lower_bound(raw.begin(), raw.end(), x);
  const double mapped = it == raw.end() ? right.back() : right[static_cast<std::size_t>(it - raw.begin())];
  return f * mapped + (1 - f) * prior_pick;
}

Calibration calibrate(const std::vector<PartPick>& picks, std::size_t slots, double threshold) {
  Calibration c;
  c.threshold = threshold;
  c.prior.assign(slots, 0.0);
  if (picks.empty()) return c;
  std::vector<std::pair<double, double>> pts;
  for (const PartPick& p : picks) {
    if (static_cast<std::size_t>(p.best) < slots) c.prior[static_cast<std::size_t>(p.best)] += 1;
    pts.emplace_back(p.margin * c.familiarity(p.d2_min), p.regret == 0 ? 1.0 : 0.0);
  }
  for (double& v : c.prior) v /= static_cast<double>(picks.size());
  isotonic(std::move(pts), c.raw, c.right);
  return c;
}

std::vector<ReliabilityBin> reliability(const std::vector<PartPick>& picks, std::size_t slots, double threshold,
                                        int bins) {
  std::vector<ReliabilityBin> out(static_cast<std::size_t>(std::max(bins, 1)));
  for (std::size_t b = 0; b < out.size(); ++b) {
    out[b].low = static_cast<double>(b) / static_cast<double>(out.size());
    out[b].high = static_cast<double>(b + 1) / static_cast<double>(out.size());
  }
  std::vector<double> conf_sum(out.size(), 0), right(out.size(), 0);
  for (std::size_t i = 0; i < picks.size(); ++i) {  // O(P² log P)
    std::vector<PartPick> others;
    others.reserve(picks.size() - 1);
    for (std::size_t j = 0; j < picks.size(); ++j)
      if (j != i) others.push_back(picks[j]);
    const Calibration c = calibrate(others, slots, threshold);
    const double conf = c.confidence(picks[i].pick, picks[i].margin, picks[i].d2_min);
    const auto b = std::min(out.size() - 1, static_cast<std::size_t>(conf * static_cast<double>(out.size())));
    out[b].parts += 1;
    conf_sum[b] += conf;
    right[b] += picks[i].regret == 0 ? 1 : 0;
  }
  for (std::size_t b = 0; b < out.size(); ++b)
    if (out[b].parts > 0) {
      out[b].mean_confidence = conf_sum[b] / static_cast<double>(out[b].parts);
      out[b].share_right = right[b] / static_cast<double>(out[b].parts);
    }
  return out;
}

}  // namespace millnet::classifier
