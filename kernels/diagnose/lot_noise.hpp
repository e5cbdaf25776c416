// Whether a lot of diagnosed channels is within noise as a whole (docs/diagnose.md "Real
// sensors"). Each channel's verdict compares its gap with the 95 % quantile of its corrected
// model's own replicas' gaps (kernels/common/quantile.hpp, linear interpolation), and that
// quantile, from a few dozen replicas, is itself a draw: a complete model's record lies beyond
// it more often than 5 % of the time. These give the chance of each channel's miss and of a
// lot's count of misses when every model is complete.
#pragma once

#include <span>

namespace allanlot::kernels {

/// The probability that a fresh draw lies beyond the interpolated kGapNoiseQuantile (0.95)
/// quantile of `replicas` draws of the same continuous distribution (quantile_sorted): with
/// h = 0.95 (R - 1), lo = floor(h), the quantile lies between the sorted draws lo + 1 and
/// lo + 2 (1-based), and the k-th of R sorted draws sits at the k / (R + 1) quantile on
/// average, so the probability is
/// (R - lo - (h - lo)) / (R + 1) (0.0790 for R = 30; exact for a uniform distribution, and
/// between (R - lo - 1) / (R + 1) and (R - lo) / (R + 1) for any continuous one). NaN for
/// fewer than 2 replicas.
double beyond_p95_probability(int replicas);

/// P(X >= k) for X the number of successes of independent trials with probabilities p
/// (Poisson-binomial; binomial when all are equal), by the exact recursion over the trials.
/// 1 for k <= 0, 0 for k > p.size(); throws std::invalid_argument for a p outside [0, 1].
double at_least_probability(std::span<const double> p, int k);

}  // namespace allanlot::kernels
