// Allan family: overlapping Allan deviation from the prefix-summed phase.
#pragma once

#include "kernels/phase.hpp"
#include "kernels/stats.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Overlapping Allan deviation, NIST SP1065 eq. (11), p. 16:
///
///   sigma^2(tau) = 1 / (2 tau^2 (N - 2m)) * sum_{i=0}^{N-2m-1} (x_{i+2m} - 2 x_{i+m} + x_i)^2
///
/// with N phase points x (PhaseData), tau = m tau0, in the channel's rate units. Terms that
/// touch a gap are left out and `n` counts the terms used. Preconditions: m >= 1.
StatResult oadev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

namespace detail {

/// Sum of squared second differences and their count, the shared core of ADEV (stride m)
/// and OADEV (stride 1), as allantools' calc_adev_phase(phase, rate, mj, stride).
struct SumCount {
  double sum = 0.0;
  std::int64_t n = 0;
};
SumCount second_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride);

}  // namespace detail
}  // namespace allanlot::kernels
