// Hadamard family: Hadamard and overlapping Hadamard deviation from the prefix-summed phase.
// Conventions (units, m_list, gaps, threads) as in kernels/allan/allan.hpp.
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"
#include "kernels/allan/sum_cache.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Hadamard deviation (non-overlapping), NIST SP1065 eq. (17), p. 20, in phase form:
///
///   H sigma^2(tau) = 1 / (6 tau^2 n) * sum_{i = 0, m, 2m, ...}
///                    (x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i)^2
///
/// with n = floor((N-1)/m) - 2 terms for gap-free data. Insensitive to linear frequency drift.
StatResult hdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Overlapping Hadamard deviation, NIST SP1065 eq. (18), p. 21:
///
///   H sigma^2(tau) = 1 / (6 tau^2 (N - 3m)) * sum_{i=0}^{N-3m-1}
///                    (x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i)^2
/// With a cache (stats.hpp), sums stored by prime_second_third are used.
StatResult ohdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0,
                 SumCache* cache = nullptr);

namespace detail {

/// Sum of squared third differences (x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i)^2 over
/// i = 0, stride, 2 stride, ... and their count: the shared core of HDEV (stride m) and
/// OHDEV (stride 1). Terms touching a gap are skipped.
SumCount third_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride);

}  // namespace detail
}  // namespace allanlot::kernels
