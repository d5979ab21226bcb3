#pragma once
// A deterministic random source for generated data. std::uniform_real_distribution is not used on
// purpose: its output is implementation-defined and changes between standard-library versions, and
// millnet promises "same seed ⇒ same bytes" on every machine.
#include <cstdint>

namespace millnet::datasets {

/// SplitMix64 (Steele, Lea & Flood 2014; the seeding generator of xoshiro). Period 2^64.
class SplitMix64 {
public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  /// Next 64 random bits.
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    return mix(z);
  }
  /// Uniform double in [0, 1): the top 53 bits, exactly representable.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform double in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [lo, hi] (inclusive). Modulo bias is < 2^-50 for the small ranges used here.
  int uniform_int(int lo, int hi) {
    const auto span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - lo + 1);
    return lo + static_cast<int>(next() % span);
  }
  /// ±1 with probability 1/2 each.
  double sign() { return (next() >> 63) != 0 ? -1.0 : 1.0; }
  /// The SplitMix64 finalizer: a bijective 64-bit mixer (used to derive independent sub-seeds).
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

private:
  std::uint64_t state_;
};

}  // namespace millnet::datasets
