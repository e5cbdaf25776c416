// Whether a lot of diagnosed channels is within noise as a whole (docs/diagnose.md "Real
// sensors"). Each channel's verdict compares its gap with the 95 % quantile of its corrected
// model's own replicas' gaps (exceedance_quantile_sorted), which a complete model's record
// exceeds 5 % of the time: a lot of hundreds of channels always has some beyond it. These give
// the chance of each channel's miss and of a lot's count of misses when every model is complete.
#pragma once

#include <span>

namespace allanlot::kernels {

/// The probability that a fresh draw lies beyond the kGapNoiseQuantile (0.95) threshold of
/// `replicas` draws of the same continuous distribution (exceedance_quantile_sorted): with
/// h = 0.95 (R + 1) - 1 clamped to 0 .. R - 1, lo = floor(h), the threshold lies between the
/// sorted draws lo + 1 and lo + 2 (1-based), and the k-th of R sorted draws sits at the
/// k / (R + 1) quantile on average, so the probability is (R - h) / (R + 1): 0.05
/// from R = 19 up (exact for any continuous distribution where h is whole, R = 19, 39, 59, ...;
/// else exact for a uniform one and between (R - lo - 1) / (R + 1) and (R - lo) / (R + 1)), and
/// 1 / (R + 1) below 19, where the threshold is the largest draw. NaN for no replicas.
double beyond_p95_probability(int replicas);

/// P(X >= k) for X the number of successes of independent trials with probabilities p
/// (Poisson-binomial; binomial when all are equal), by the exact recursion over the trials.
/// 1 for k <= 0, 0 for k > p.size(); throws std::invalid_argument for a p outside [0, 1].
double at_least_probability(std::span<const double> p, int k);

}  // namespace allanlot::kernels
