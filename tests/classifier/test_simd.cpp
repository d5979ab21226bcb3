// The classifier's private kernels: the exp that the leave-one-out pass evaluates per stored pair
// (classifier/src/simd.hpp) against std::exp, and the selection of each vector's R nearest
// (classifier/src/engine.hpp) against std::nth_element.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "engine.hpp"
#include "simd.hpp"

namespace {

using millnet::classifier::detail::exp_neg_scaled;
using millnet::classifier::detail::exp_nonpositive;
using millnet::classifier::detail::FlushToZero;
using millnet::classifier::detail::Lane;

// Distance in units in the last place between two positive finite doubles.
std::int64_t ulp_distance(double a, double b) {
  std::int64_t ia = 0, ib = 0;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return ia > ib ? ia - ib : ib - ia;
}

double exp1(double x) {
  Lane l{};
  l += x;
  return exp_nonpositive(l)[0];
}

}  // namespace

TEST(Simd, ExpIsWithinTwoUlpOfStdExpOnMinus700ToZero) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> wide(-700.0, 0.0), narrow(-1e-3, 0.0);
  std::int64_t worst = 0;
  double worst_x = 0;
  for (int t = 0; t < 2'000'000; ++t) {
    const double x = t % 3 == 0 ? narrow(rng) : wide(rng);
    const std::int64_t d = ulp_distance(exp1(x), std::exp(x));
    if (d > worst) {
      worst = d;
      worst_x = x;
    }
  }
  // reduction boundaries (x = k·ln2 ± tiny) and powers of two near 0
  for (int k = 0; k <= 1009; ++k)
    for (double e : {-1e-12, 0.0, 1e-12}) {
      const double x = std::min(0.0, -k * 0.6931471805599453 + e);
      worst = std::max(worst, ulp_distance(exp1(x), std::exp(x)));
    }
  for (int p = 1; p < 1000; ++p) {
    const double x = -std::ldexp(1.0, -p);
    worst = std::max(worst, ulp_distance(exp1(x), std::exp(x)));
  }
  EXPECT_LE(worst, 2) << "worst at x = " << worst_x;
  EXPECT_EQ(exp1(0.0), 1.0);
  EXPECT_EQ(exp1(-0.0), 1.0);
}

TEST(Simd, ScaledExpFloorsTailsAndInfinityAndIgnoresTheThreadMode) {
  // n = 19: two full lanes and a tail of 3; +inf (an excluded vector) and far values become 0
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> delta = {0.0,  0.5, 1.0,  2.0,   10.0,  100.0, 344.0, 346.0, inf, 3.0,
                               1e-9, 7.0, 0.25, 699.0, 701.0, 1e6,   0.125, 50.0,  inf};
  const double u = 1.0, floor = 1e-150;
  std::vector<double> out(delta.size(), -1.0);
  exp_neg_scaled(delta.data(), u, floor, out.data(), static_cast<Eigen::Index>(delta.size()));
  for (std::size_t j = 0; j < delta.size(); ++j) {
    const double ref = std::exp(-delta[j] * u);
    if (ref < floor) {
      EXPECT_EQ(out[j], 0.0) << "j " << j;
    } else {
      EXPECT_LE(ulp_distance(out[j], ref), 2) << "j " << j;
    }
  }
  // in place, and under flush-to-zero (the power-sum kernels' mode): the same bits
  std::vector<double> again = delta;
  {
    const FlushToZero ftz;
    exp_neg_scaled(again.data(), u, floor, again.data(), static_cast<Eigen::Index>(again.size()));
  }
  EXPECT_EQ(std::memcmp(again.data(), out.data(), sizeof(double) * out.size()), 0);
  // the mode is restored: a subnormal product survives again
  volatile double tiny = 1e-300;
  EXPECT_GT(tiny * 1e-10, 0.0);
}

TEST(NearestCut, EqualsNthElementOnRandomTiedAndAdversarialRows) {
  using millnet::classifier::detail::nearest_cut;
  using millnet::classifier::detail::NearestBuffers;
  std::mt19937_64 rng(77);
  NearestBuffers B;
  int sampled_rows = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Index n = std::uniform_int_distribution<Eigen::Index>(1, 9000)(rng);
    const Eigen::Index R = std::uniform_int_distribution<Eigen::Index>(1, 300)(rng);
    std::vector<double> d(static_cast<std::size_t>(n));
    const int kind = trial % 4;
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      if (kind == 0) d[uj] = std::uniform_real_distribution<double>(0, 100)(rng);                  // random
      if (kind == 1) d[uj] = static_cast<double>(std::uniform_int_distribution<int>(0, 20)(rng));  // many ties
      if (kind == 2) d[uj] = static_cast<double>(n - j);                           // descending: every sample is large
      if (kind == 3) d[uj] = j % 97 == 0 ? 0.5 : 1000.0 + static_cast<double>(j);  // the near few off the sample grid
    }
    const double cut = nearest_cut(d.data(), n, R, B);
    std::vector<double> ref = d;
    double want = std::numeric_limits<double>::infinity();
    if (R < n) {
      std::nth_element(ref.begin(), ref.begin() + R, ref.end());
      want = ref[static_cast<std::size_t>(R)];
    }
    ASSERT_EQ(cut, want) << "trial " << trial << " n " << n << " R " << R;
    // the candidates: ascending, and a superset of {j : d_j < cut}
    ASSERT_TRUE(std::is_sorted(B.idx.begin(), B.idx.end()));
    std::vector<std::int32_t> below;
    for (Eigen::Index j = 0; j < n; ++j)
      if (d[static_cast<std::size_t>(j)] < cut) below.push_back(static_cast<std::int32_t>(j));
    ASSERT_TRUE(std::includes(B.idx.begin(), B.idx.end(), below.begin(), below.end())) << "trial " << trial;
    sampled_rows += static_cast<Eigen::Index>(B.idx.size()) < n ? 1 : 0;
  }
  EXPECT_GT(sampled_rows, 50);  // the sampled-pivot path ran, not only the full fallback
}
