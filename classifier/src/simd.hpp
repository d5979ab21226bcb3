#pragma once
// Private vector kernels of the classifier: an 8-lane double type and exp over non-positive
// arguments, the one transcendental the leave-one-out pass evaluates per stored pair.
//
// Why our own exp: Eigen 3.4's vectorized exp costs ≈ 2.2 ns per value on the target machine
// (AVX-512), and the α scan evaluates several per pair, N² pairs; this one costs ≈ 1.1 ns with
// ≤ 1 ulp error over [−700, 0] (measured against std::exp in tests/classifier). It is written
// with GCC/Clang vector extensions, so it compiles to AVX-512, AVX2 or SSE2 alike, and it is
// pure arithmetic: the same inputs give the same bits whatever thread evaluates them.
#include <cstdint>
#include <cstring>

#include <Eigen/Core>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace millnet::classifier::detail {

constexpr int kLanes = 8;
/// Lowered to one AVX-512, two AVX2 or four SSE2 registers, whatever the target has.
typedef double Lane __attribute__((vector_size(kLanes * sizeof(double))));
typedef std::int64_t ILane __attribute__((vector_size(kLanes * sizeof(std::int64_t))));

/// exp(x) for x ≤ 0 (x = −inf gives exp(−700) ≈ 1e-304: callers floor such values to 0).
/// Cody–Waite reduction x = k·ln2 + r, |r| ≤ ln2/2 (ln2 split in a 32-bit-exact high part and a
/// low part, so k·ln2_hi is exact), Taylor polynomial of degree 13 in Horner form (truncation
/// < 4e-18 relative), then the 2^k scale built in the exponent bits. Arguments below −700 are
/// clamped to −700 (k ≥ −1010: the scale stays a normal number).
inline Lane exp_nonpositive(Lane x) {
  const Lane lo = Lane{} - 700.0;
  x = x < lo ? lo : x;                            // also maps −inf (and keeps NaN out of the integer path below)
  const Lane magic = Lane{} + 0x1.8p52;           // adding it rounds to an integer held in the low mantissa bits
  const Lane t = x * 1.4426950408889634 + magic;  // x / ln 2
  const Lane k = t - magic;
  Lane r = x - k * 0x1.62e42fee00000p-1;  // ln 2, high 32 bits
  r = r - k * 0x1.a39ef35793c76p-33;      // ln 2 − high part
  Lane p = Lane{} + 1.0 / 6227020800.0;   // 1/13!
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  ILane ti, tm;
  std::memcpy(&ti, &t, sizeof ti);
  std::memcpy(&tm, &magic, sizeof tm);
  const ILane bits = ((ti - tm) + 1023) << 52;  // 2^k
  Lane scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

/// out[j] = exp(−delta[j]·u), set to 0 below `floor`, for j < n; delta ≥ 0 (+inf allowed: 0),
/// u > 0. out may alias delta. O(n).
inline void exp_neg_scaled(const double* delta, double u, double floor, double* out, Eigen::Index n) {
  const Lane zero{};
  const Lane fl = zero + floor;
  const Lane nu = zero - u;
  const auto lane = [&](Lane x) {
    x = exp_nonpositive(x * nu);
    return x < fl ? zero : x;
  };
  Eigen::Index j = 0;
  for (; j + kLanes <= n; j += kLanes) {  // fixed-size copies: they stay in registers
    Lane x;
    std::memcpy(&x, delta + j, sizeof x);
    x = lane(x);
    std::memcpy(out + j, &x, sizeof x);
  }
  if (j < n) {  // tail: the same lane arithmetic on a zero-padded lane (a variable-size copy is a
                // library call, measured 2x the whole LOO time when used for every lane)
    const auto bytes = static_cast<std::size_t>(n - j) * sizeof(double);
    Lane x{};
    std::memcpy(&x, delta + j, bytes);
    x = lane(x);
    std::memcpy(out + j, &x, bytes);
  }
}

/// While alive, the calling thread's floating-point unit flushes subnormal results and operands
/// to zero (x86 MXCSR FTZ|DAZ), so repeated squaring or scaling of similarities underflows
/// straight to 0 instead of through the subnormal range, where each operation costs a microcode
/// assist (~100 cycles). Restores the previous mode. Elsewhere `kFlushesToZero` is false and the
/// kernels compare against an explicit floor instead.
#if defined(__SSE2__)
inline constexpr bool kFlushesToZero = true;
class FlushToZero {
public:
  FlushToZero() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }
  ~FlushToZero() { _mm_setcsr(saved_); }
  FlushToZero(const FlushToZero&) = delete;
  FlushToZero& operator=(const FlushToZero&) = delete;

private:
  unsigned saved_;
};
#else
inline constexpr bool kFlushesToZero = false;
struct FlushToZero {};
#endif

}  // namespace millnet::classifier::detail
