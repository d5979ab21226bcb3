// Zigzag chains inside monotone faces and the order of the faces (scan frame).
#include "zigzag.hpp"

#include "millnet/pocket/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace millnet::pocket {

namespace {
constexpr double kZigzagInf = std::numeric_limits<double>::infinity();

double zigzag_polyline_length(const std::vector<Vec2>& pts) {
  double l = 0;
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) l += (pts[k + 1] - pts[k]).norm();
  return l;
}

void push_unique(std::vector<Vec2>& out, const Vec2& p) {
  if (out.empty() || (out.back() - p).norm() > tol::join_mm) out.push_back(p);
}
}  // namespace

std::vector<double> pass_heights(const std::vector<PolyArea>& areas, const std::vector<Srp>& srps, double stepover) {
  // Breakpoints: a pass just inside every y-extremum of every loop (area bottom/top, island
  // tops/bottoms, prong tips…), so that a flat wall facing the passes is always run along instead
  // of leaving a band up to a stepover thick; between breakpoints, even spacing ≤ stepover.
  // O(E log E + passes · n_s), E = extrema.
  std::vector<double> br;
  for (const Srp& e : find_extrema(areas)) {
    // Maxima get a pass just below, minima just above (inside the area on the side it occupies).
    const bool area_below = (e.kind == SrpKind::R) != e.reflex;
    br.push_back(e.p.y() + (area_below ? -tol::scan_clear_mm : tol::scan_clear_mm));
  }
  std::sort(br.begin(), br.end());
  std::vector<double> merged;
  for (double y : br)
    if (merged.empty() || y - merged.back() > tol::gouge_check_mm) merged.push_back(y);
  std::vector<double> ys;
  for (std::size_t k = 0; k < merged.size(); ++k) {
    ys.push_back(merged[k]);
    if (k + 1 == merged.size()) break;
    const double gap = merged[k + 1] - merged[k];
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(gap / stepover - 1e-9)));
    for (std::size_t i = 1; i < n; ++i) ys.push_back(merged[k] + gap * static_cast<double>(i) / static_cast<double>(n));
  }
  // Keep passes out of the slits at SRP heights: O(passes · n_s), a few rounds for stacked SRPs.
  for (double& y : ys)
    for (int round = 0; round < 4; ++round) {
      bool moved = false;
      for (const Srp& s : srps)
        if (std::abs(y - s.p.y()) < tol::scan_clear_mm * (1 - 1e-9)) {
          y = s.p.y() + (y >= s.p.y() ? tol::scan_clear_mm : -tol::scan_clear_mm);
          moved = true;
        }
      if (!moved) break;
    }
  std::sort(ys.begin(), ys.end());
  return ys;
}

FaceZigzag::FaceZigzag(const PolyArea& face, const std::vector<double>& ys) : ring_(face.outer) {
  const std::size_t n = ring_.size();
  double lo = kZigzagInf, hi = -kZigzagInf;
  for (const Vec2& v : ring_) {
    lo = std::min(lo, v.y());
    hi = std::max(hi, v.y());
  }
  auto scan = [&](double y) {
    // Crossings of the outer ring by the closed-open rule, O(n). Holes (none in a monotone face)
    // only make the face non-monotone; their passes are split off below.
    std::vector<End> xs;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& a = ring_[k];
      const Vec2& b = ring_[(k + 1) % n];
      if ((a.y() > y) != (b.y() > y))
        xs.push_back({Vec2(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()), y), k});
    }
    std::sort(xs.begin(), xs.end(), [](const End& u, const End& v) { return u.p.x() < v.p.x(); });
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) (k == 0 ? passes_ : extra_).push_back({xs[k], xs[k + 1]});
  };
  for (double y : ys)
    if (y >= lo && y <= hi) scan(y);  // O(passes · n)
  if (passes_.empty() && hi > lo) scan(0.5 * (lo + hi));
  if (!face.holes.empty()) {
    // Not monotone: keep every interval as its own chain (never expected from partition()).
    for (const Pass& p : passes_) extra_.push_back(p);
    passes_.clear();
  }
}

Vec2 FaceZigzag::entry(int corner) const {
  const Pass& p = (corner & 1) ? passes_.back() : passes_.front();
  return (corner & 2) ? p.right.p : p.left.p;
}

Vec2 FaceZigzag::exit(int corner) const {
  const Pass& p = (corner & 1) ? passes_.front() : passes_.back();
  const bool start_right = (corner & 2) != 0;
  // The first pass runs away from the start side; after an odd number of passes we are on the
  // other side.
  const bool end_right = (passes_.size() % 2 == 1) ? !start_right : start_right;
  return end_right ? p.right.p : p.left.p;
}

std::vector<Vec2> FaceZigzag::walk(const End& a, const End& b) const {
  // Both ways around the ring from a to b; the shorter one is kept. O(n).
  const std::size_t n = ring_.size();
  std::vector<Vec2> fwd{a.p}, bwd{a.p};
  if (a.edge != b.edge) {
    for (std::size_t k = (a.edge + 1) % n;; k = (k + 1) % n) {
      fwd.push_back(ring_[k]);
      if (k == b.edge) break;
    }
    for (std::size_t k = a.edge;; k = (k + n - 1) % n) {
      bwd.push_back(ring_[k]);
      if (k == (b.edge + 1) % n) break;
    }
  }
  fwd.push_back(b.p);
  bwd.push_back(b.p);
  return zigzag_polyline_length(fwd) <= zigzag_polyline_length(bwd) ? fwd : bwd;
}

std::vector<Vec2> FaceZigzag::chain(int corner) const {
  std::vector<Vec2> out;
  const std::size_t m = passes_.size();
  bool right = (corner & 2) != 0;  // side where the current pass starts
  for (std::size_t i = 0; i < m; ++i) {
    const Pass& p = passes_[(corner & 1) ? m - 1 - i : i];
    const End& s = right ? p.right : p.left;
    const End& e = right ? p.left : p.right;
    if (i > 0) {
      const Pass& prev = passes_[(corner & 1) ? m - i : i - 1];
      const End& pe = right ? prev.right : prev.left;  // previous pass ended on this side
      for (const Vec2& v : walk(pe, s)) push_unique(out, v);
    }
    push_unique(out, s.p);
    push_unique(out, e.p);
    right = !right;
  }
  if (out.size() == 1) out.push_back(out.front());  // a point-like pass: a plunge only
  return out;
}

std::vector<std::vector<Vec2>> FaceZigzag::extra_chains() const {
  std::vector<std::vector<Vec2>> out;
  for (const Pass& p : extra_) out.push_back({p.left.p, p.right.p});
  return out;
}

namespace {
/// Optimal corners for a fixed order by DP: O(n · 16). Returns rapid + item length.
double best_corners(const std::vector<OrderItem>& items, const std::vector<std::size_t>& order,
                    std::vector<int>* corner) {
  const std::size_t n = order.size();
  if (n == 0) return 0;
  std::vector<std::array<double, 4>> cost(n);
  std::vector<std::array<int, 4>> from(n);
  for (std::size_t c = 0; c < 4; ++c) cost[0][c] = items[order[0]].length[c];
  for (std::size_t i = 1; i < n; ++i)
    for (int c = 0; c < 4; ++c) {
      cost[i][static_cast<std::size_t>(c)] = kZigzagInf;
      for (int d = 0; d < 4; ++d) {
        const double v =
            cost[i - 1][static_cast<std::size_t>(d)] +
            (items[order[i - 1]].exit[static_cast<std::size_t>(d)] - items[order[i]].entry[static_cast<std::size_t>(c)])
                .norm() +
            items[order[i]].length[static_cast<std::size_t>(c)];
        if (v < cost[i][static_cast<std::size_t>(c)]) {
          cost[i][static_cast<std::size_t>(c)] = v;
          from[i][static_cast<std::size_t>(c)] = d;
        }
      }
    }
  int c = 0;
  for (int d = 1; d < 4; ++d)
    if (cost[n - 1][static_cast<std::size_t>(d)] < cost[n - 1][static_cast<std::size_t>(c)]) c = d;
  const double best = cost[n - 1][static_cast<std::size_t>(c)];
  if (corner) {
    corner->assign(n, 0);
    for (std::size_t i = n; i-- > 0;) {
      (*corner)[i] = c;
      if (i > 0) c = from[i][static_cast<std::size_t>(c)];
    }
  }
  return best;
}
}  // namespace

Ordering order_items(const std::vector<OrderItem>& items) {
  Ordering res;
  const std::size_t n = items.size();
  if (n == 0) return res;
  // Nearest neighbour from item 0 (its exits averaged over corners): O(n² · 16).
  std::vector<char> used(n, 0);
  std::vector<std::size_t> order{0};
  used[0] = 1;
  while (order.size() < n) {
    const OrderItem& last = items[order.back()];
    std::size_t pick = n;
    double bd = kZigzagInf;
    for (std::size_t j = 0; j < n; ++j) {
      if (used[j]) continue;
      for (std::size_t a = 0; a < 4; ++a)
        for (std::size_t b = 0; b < 4; ++b) {
          const double d = (last.exit[a] - items[j].entry[b]).norm();
          if (d < bd) {
            bd = d;
            pick = j;
          }
        }
    }
    used[pick] = 1;
    order.push_back(pick);
  }
  double best = best_corners(items, order, nullptr);
  // 2-opt (segment reversal) and single-item moves, first improvement. Each trial costs one
  // O(n·16) corner DP, a sweep O(n²) trials: the search stops after kOrderBudget·16 DP steps in
  // all (deterministic), so that parts with many regions (a sliced mesh level with dozens of
  // islands, tried at every candidate angle) keep a bounded planning time. O(min(sweeps·n³, budget)).
  constexpr double kOrderBudget = 2e6;
  long trials_left = static_cast<long>(kOrderBudget / static_cast<double>(n));
  for (int sweep = 0; sweep < 50 && trials_left > 0; ++sweep) {
    bool improved = false;
    for (std::size_t i = 0; i + 1 < n && !improved && trials_left > 0; ++i)
      for (std::size_t j = i + 1; j < n && !improved && --trials_left > 0; ++j) {
        auto trial = order;
        std::reverse(trial.begin() + static_cast<std::ptrdiff_t>(i),
                     trial.begin() + static_cast<std::ptrdiff_t>(j) + 1);
        const double c = best_corners(items, trial, nullptr);
        if (c < best - tol::improvement_mm) {
          best = c;
          order = std::move(trial);
          improved = true;
        }
      }
    for (std::size_t i = 0; i < n && !improved && trials_left > 0; ++i)
      for (std::size_t j = 0; j < n && !improved && --trials_left > 0; ++j) {
        if (i == j) continue;
        auto trial = order;
        const std::size_t v = trial[i];
        trial.erase(trial.begin() + static_cast<std::ptrdiff_t>(i));
        trial.insert(trial.begin() + static_cast<std::ptrdiff_t>(j), v);
        const double c = best_corners(items, trial, nullptr);
        if (c < best - tol::improvement_mm) {
          best = c;
          order = std::move(trial);
          improved = true;
        }
      }
    if (!improved) break;
  }
  best_corners(items, order, &res.corner);
  res.order = std::move(order);
  for (std::size_t i = 0; i < n; ++i) {
    const OrderItem& it = items[res.order[i]];
    const auto c = static_cast<std::size_t>(res.corner[i]);
    res.item_length += it.length[c];
    if (i > 0)
      res.rapid_length +=
          (items[res.order[i - 1]].exit[static_cast<std::size_t>(res.corner[i - 1])] - it.entry[c]).norm();
  }
  return res;
}

}  // namespace millnet::pocket
