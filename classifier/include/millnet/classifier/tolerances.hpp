#pragma once
// Named numerical constants of the classifier. Inputs are z-scored, so distances here are
// dimensionless (squared standard deviations), not mm.
#include <cmath>

namespace millnet::classifier::tol {

/// Similarities below this are set to exactly 0 when the leave-one-out pass computes them; the
/// α scan's squaring chains then run with flush-to-zero (or, on targets without it, compare
/// against this floor at every step), so that no value becomes a (slow) subnormal. Relative to
/// the nearest vector (s = 1) the neglected mass is < N·1e-150.
inline constexpr double kSimilarityFloor = 1e-150;

/// A stored vector whose similarity is < exp(-(kTruncationMargin + ln N)) relative to the nearest
/// one is negligible at double precision (their total < e^-40 ≈ 4e-18). The neighbour cache is
/// used at α only when every vector it dropped lies beyond that margin.
inline constexpr double kTruncationMargin = 40.0;

/// A column whose population standard deviation is below this (in its own units) is "constant":
/// its std is stored as 1 so that z-scoring subtracts the mean and divides by nothing.
inline constexpr double kConstantColumnStd = 1e-12;

/// Looser margin for the golden-section evaluations only (not for any reported figure): dropped
/// similarities < e^-(20 + ln N) each, so the RMS being minimized is off by < ~1e-8 relative,
/// far below what moves the optimum. The final figures and outputs use kTruncationMargin.
inline constexpr double kRefineTruncationMargin = 20.0;

/// The regret counted for picking a strategy that scores 0 on a part (it gouges or misses the
/// surface specification, issue 39): as if the part were machined twice — the time of a second
/// finishing, the best one, on top of the first. A real miss may cost more (a scrapped part);
/// the count of misses is reported beside every mean.
inline constexpr double kMissRegret = 1.0;

}  // namespace millnet::classifier::tol
