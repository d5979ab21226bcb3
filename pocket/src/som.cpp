#include "millnet/pocket/som.hpp"

#include "millnet/core/error.hpp"
#include "node_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>

namespace millnet::pocket {

namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

using detail::NodeGrid;

/// The grid's nearest node to city i; found-nothing (every squared distance overflowed) is an error,
/// never an index (issue 15: /pocket/som/w 1e307 indexed with -1 and corrupted the heap).
std::pair<std::size_t, double> nearest_node(const NodeGrid& grid, const std::vector<Vec2>& X, std::size_t i,
                                            const std::vector<Vec2>& C, double w) {
  const auto [j, d2] = grid.nearest(X[i], C);
  if (j < 0)
    throw Error("som_tour: no ring node at a finite distance from tool point " + std::to_string(i) +
                " (coordinates scaled by w = " + std::to_string(w) + " overflow)");
  return {static_cast<std::size_t>(j), d2};
}

void check_som_params(const SomParams& p) {
  auto bad = [](const std::string& key, const std::string& what) {
    return Error("som parameters: '" + key + "' " + what);
  };
  if (!(p.node_factor >= 1.0) || !std::isfinite(p.node_factor)) throw bad("node_factor", "must be ≥ 1");
  if (!(p.g0 >= 0) || !std::isfinite(p.g0)) throw bad("g0", "must be ≥ 0 (0 = auto)");
  if (!p.adaptive_alpha && !(p.alpha > 0 && p.alpha < 1)) throw bad("alpha", "must be in (0, 1)");
  if (p.adaptive_alpha) {
    if (!(p.c > 0) || !std::isfinite(p.c)) throw bad("c", "must be > 0");
    if (!(p.k_scale_mm > 0) || !std::isfinite(p.k_scale_mm)) throw bad("k_scale_mm", "must be > 0");
    if (!(p.alpha_min > 0 && p.alpha_min < 1)) throw bad("alpha_min", "must be in (0, 1)");
  }
  if (!(p.w > 0) || !std::isfinite(p.w)) throw bad("w", "must be > 0");
  if (p.max_passes < 1) throw bad("max_passes", "must be ≥ 1");
  if (!(p.tolerance_mm >= 0) || !std::isfinite(p.tolerance_mm)) throw bad("tolerance_mm", "must be ≥ 0");
}

}  // namespace

Rng::Rng(std::uint64_t seed) {
  std::uint64_t x = seed;
  for (auto& s : s_) s = splitmix64(x);
}

std::uint64_t Rng::next() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double Rng::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

std::size_t Rng::below(std::size_t n) { return static_cast<std::size_t>(next() % static_cast<std::uint64_t>(n)); }

double tour_length(const std::vector<Vec2>& pts, const std::vector<int>& order, bool closed) {
  double len = 0;
  for (std::size_t k = 1; k < order.size(); ++k)  // O(N)
    len += (pts[static_cast<std::size_t>(order[k])] - pts[static_cast<std::size_t>(order[k - 1])]).norm();
  if (closed && order.size() > 2)
    len += (pts[static_cast<std::size_t>(order.front())] - pts[static_cast<std::size_t>(order.back())]).norm();
  return len;
}

bool is_permutation_of(const std::vector<int>& order, std::size_t n) {
  if (order.size() != n) return false;
  std::vector<char> seen(n, 0);
  for (int i : order) {  // O(n)
    if (i < 0 || static_cast<std::size_t>(i) >= n || seen[static_cast<std::size_t>(i)]) return false;
    seen[static_cast<std::size_t>(i)] = 1;
  }
  return true;
}

namespace {

/// The cities in the w-scaled plane (x, sqrt(w)·y), where the weighted metric of eq. 6 is
/// Euclidean, and their bounding box there.
struct ScaledCities {
  std::vector<Vec2> X;
  Vec2 lo, hi;
};

ScaledCities scale_cities(const std::vector<Vec2>& cities, double sw, double w) {
  ScaledCities s;
  s.X.resize(cities.size());
  s.lo = Vec2(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  s.hi = -s.lo;
  for (std::size_t i = 0; i < cities.size(); ++i) {  // O(N)
    s.X[i] = Vec2(cities[i].x(), sw * cities[i].y());
    s.lo = s.lo.cwiseMin(s.X[i]);
    s.hi = s.hi.cwiseMax(s.X[i]);
  }
  // Every squared distance in the scaled plane is at most the box diagonal's square: it must be finite.
  if (!std::isfinite((s.hi - s.lo).squaredNorm()))
    throw Error("som parameters: 'w' = " + std::to_string(w) +
                " scales the tool points beyond the range of squared distances (lower w)");
  return s;
}

/// The distance within which every city must have its own node (the mapping's tolerance), in the
/// scaled plane: tolerance_mm, or a hundredth of the mean spacing of N cities over the box.
double mapping_tolerance(const SomParams& params, const ScaledCities& s, std::size_t n, double sw) {
  double tol = params.tolerance_mm;
  if (tol == 0) {
    const Vec2 ext = s.hi - s.lo;
    const double a = std::max(ext.x() * ext.y(), std::pow(std::max(ext.x(), ext.y()) / static_cast<double>(n), 2));
    tol = 0.01 * std::sqrt(a / static_cast<double>(n));
  }
  return tol * std::min(1.0, sw);  // a tolerance in mm is at least as strict in the scaled plane
}

/// Initial ring: an ellipse at half the cities' bounding box around its centre, random phase. It
/// already has the global order of a good tour (no knots), and spreads nodes where cities are.
std::vector<Vec2> initial_ring(const ScaledCities& s, std::size_t m, Rng& rng) {
  const double md = static_cast<double>(m);
  const Vec2 ctr = 0.5 * (s.lo + s.hi);
  const Vec2 half = 0.5 * (s.hi - s.lo);
  const double phase = 2 * std::numbers::pi * rng.uniform();
  std::vector<Vec2> C(m);
  for (std::size_t j = 0; j < m; ++j) {  // O(M)
    const double t = phase + 2 * std::numbers::pi * static_cast<double>(j) / md;
    C[j] = ctr + Vec2(0.5 * half.x() * std::cos(t), 0.5 * half.y() * std::sin(t));
  }
  return C;
}

/// One adaptation pass: the cities in a fresh random order (Fisher–Yates), each pulling its winner
/// node and the `width` ring neighbours on either side toward it by the gain kernel f. Returns
/// Σ |city − winner|² before the pulls. O(N·(query + width)).
double adapt_pass(const ScaledCities& s, std::vector<Vec2>& C, NodeGrid& grid, const std::vector<double>& f,
                  std::ptrdiff_t width, std::vector<std::size_t>& perm, Rng& rng, double w) {
  const std::size_t n = s.X.size();
  for (std::size_t k = n - 1; k > 0; --k) std::swap(perm[k], perm[rng.below(k + 1)]);  // Fisher–Yates
  double k2 = 0;
  const auto mi = static_cast<std::ptrdiff_t>(C.size());
  for (std::size_t idx = 0; idx < n; ++idx) {
    const Vec2& x = s.X[perm[idx]];
    const auto jc = static_cast<std::ptrdiff_t>(nearest_node(grid, s.X, perm[idx], C, w).first);
    std::ptrdiff_t j = jc - width;
    if (j < 0) j += mi;
    for (std::ptrdiff_t k = -width; k <= width; ++k, ++j) {
      if (j == mi) j = 0;
      const auto ju = static_cast<std::size_t>(j);
      C[ju] += f[static_cast<std::size_t>(k < 0 ? -k : k)] * (x - C[ju]);
      grid.moved(static_cast<int>(j), C[ju]);
    }
    k2 += (x - C[static_cast<std::size_t>(jc)]).squaredNorm();
  }
  return k2;
}

/// Every city has its own node within tol (owner: the city of each node, or -1). O(N·query).
bool every_city_mapped(const NodeGrid& grid, const ScaledCities& s, const std::vector<Vec2>& C, double w, double tol2,
                       std::vector<int>& owner) {
  std::fill(owner.begin(), owner.end(), -1);
  for (std::size_t i = 0; i < s.X.size(); ++i) {
    const auto [j, d2] = nearest_node(grid, s.X, i, C, w);
    if (d2 > tol2 || owner[j] >= 0) return false;
    owner[j] = static_cast<int>(i);
  }
  return true;
}

/// The tour: cities by (winner node, position along the ring direction at that node, index), into
/// res.order; res.shared_nodes counts the cities whose winner another city had. O(N log N).
void tour_from_ring(const NodeGrid& grid, const ScaledCities& s, const std::vector<Vec2>& C, double w,
                    std::vector<int>& owner, SomResult& res) {
  const std::size_t n = s.X.size(), m = C.size();
  std::vector<std::tuple<int, double, int>> key(n);
  std::fill(owner.begin(), owner.end(), -1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t ju = nearest_node(grid, s.X, i, C, w).first;
    const int j = static_cast<int>(ju);
    const Vec2 dir = C[(ju + 1) % m] - C[(ju + m - 1) % m];
    key[i] = {j, (s.X[i] - C[ju]).dot(dir), static_cast<int>(i)};
    if (owner[ju] >= 0) ++res.shared_nodes;
    owner[ju] = static_cast<int>(i);
  }
  std::sort(key.begin(), key.end());
  res.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) res.order[i] = std::get<2>(key[i]);
}

/// The gain G₀ in ring nodes. Auto: quality barely depends on G₀ here (the elliptic initial ring
/// already carries the global order), while the cost of the early passes grows as N·G₀/α; 30 ring
/// nodes was the knee on 1k–10k random and grid points (tour within 0.5 % of G₀ = 100, 3× faster).
double initial_gain(const SomParams& params, double md) {
  return params.g0 > 0 ? params.g0 : std::clamp(0.1 * md, 3.0, 30.0);
}

/// The ring neighbours pulled on either side of the winner at gain G: f(n) > 1e-6·f(0) ⇔ |n| < G·reach.
double kernel_width(double G, double md) {
  const double reach = std::sqrt(std::log(1e6));
  return std::min(std::floor(G * reach), std::floor((md - 1) / 2));
}

/// Passes after G has shrunk to the winner alone: two cities that share a node keep pulling it to
/// and fro once G is tiny; after a few passes nothing changes the order any more.
constexpr int kSettlePasses = 20;

}  // namespace

double som_node_steps(double n, const SomParams& params) {
  const double md = std::max(3.0, std::round(params.node_factor * n));
  // The slowest decay the run can take: α, or the adaptive α's floor.
  const double alpha = params.adaptive_alpha ? params.alpha_min : params.alpha;
  double G = initial_gain(params, md), per_city = 1;  // + the tour's own winner query
  int settled = 0;
  for (int pass = 0; pass < params.max_passes; ++pass) {  // O(passes)
    const double width = kernel_width(G, md);
    per_city += 2 * width + 2;  // the pulls and the winner query
    G *= (1 - alpha);
    if (width == 0) {
      per_city += 1;  // the mapping check's query
      if (++settled >= kSettlePasses) break;
    }
  }
  return n * per_city;
}

SomResult som_tour(const std::vector<Vec2>& cities, const SomParams& params) {
  check_som_params(params);
  const std::size_t n = cities.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(cities[i].x()) || !std::isfinite(cities[i].y()))
      throw Error("som_tour: city " + std::to_string(i) + " is not finite");
  SomResult res;
  if (n <= 3) {  // every order of ≤ 3 cities is optimal
    for (std::size_t i = 0; i < n; ++i) res.order.push_back(static_cast<int>(i));
    res.converged = true;
    return res;
  }
  // Work in the w-scaled plane: the update C += f·(X − C) is linear, so nothing needs to be scaled back.
  const double sw = std::sqrt(params.w);
  const ScaledCities s = scale_cities(cities, sw, params.w);
  const std::size_t m =
      std::max<std::size_t>(3, static_cast<std::size_t>(std::llround(params.node_factor * static_cast<double>(n))));
  res.nodes = m;
  const double md = static_cast<double>(m);
  const double tol = mapping_tolerance(params, s, n, sw);
  const double tol2 = tol * tol;

  Rng rng(params.seed);
  std::vector<Vec2> C = initial_ring(s, m, rng);
  NodeGrid grid(s.lo, s.hi, m / 2);
  for (std::size_t j = 0; j < m; ++j) grid.insert(static_cast<int>(j), C[j]);

  double G = initial_gain(params, md);
  const double f0 = 1.0 / std::numbers::sqrt2;
  std::vector<std::size_t> perm(n);
  for (std::size_t i = 0; i < n; ++i) perm[i] = i;
  std::vector<double> f;
  std::vector<int> owner(m, -1);

  int settled = 0;
  for (int pass = 0; pass < params.max_passes; ++pass) {
    const auto width = static_cast<std::ptrdiff_t>(kernel_width(G, md));
    f.assign(static_cast<std::size_t>(width) + 1, 0.0);
    for (std::ptrdiff_t k = 0; k <= width; ++k) {  // O(width)
      const double kd = static_cast<double>(k);
      f[static_cast<std::size_t>(k)] = f0 * std::exp(-kd * kd / (G * G));
    }
    const double k2 = adapt_pass(s, C, grid, f, width, perm, rng, params.w);
    res.passes = pass + 1;
    double alpha = params.alpha;
    if (params.adaptive_alpha) {
      const double K = std::sqrt(k2) / params.k_scale_mm;
      alpha = std::clamp(params.c * std::log1p(std::exp(-K)), params.alpha_min, 0.9);
    }
    G *= (1 - alpha);
    if (width == 0) {
      if (every_city_mapped(grid, s, C, params.w, tol2, owner)) {
        res.converged = true;
        break;
      }
      // Two cities that share a node keep pulling it to and fro once G is tiny; after a few passes
      // nothing changes the order any more (they are then ordered along the ring direction).
      if (++settled >= kSettlePasses) break;
    }
  }
  res.final_gain = G;
  tour_from_ring(grid, s, C, params.w, owner, res);
  MILLNET_ASSERT(is_permutation_of(res.order, n), "SOM tour is not a permutation of the cities");
  if (!is_permutation_of(res.order, n)) throw Error("som_tour: internal error, tour is not a permutation");
  return res;
}

}  // namespace millnet::pocket
