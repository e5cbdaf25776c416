// Parabolic deviation PDEV (Vernotte, Lenczner, Bourgeois & Rubiola, "The parabolic variance
// (PVAR): a wavelet variance based on the least-square fit", IEEE Trans. UFFC 63 (2016), with
// the phase-domain estimator of Vernotte et al., Metrologia 57 (2020)): the variance of the
// Omega (least-squares) frequency estimate, the stability measure of frequency counters that
// fit a line to the phase. Conventions (units, m_list, threads, m < 1) as in
// kernels/allan/allan.hpp, except gaps: refused with std::invalid_argument (the running sums
// below have no term to skip).
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Parabolic deviation in phase form, for m >= 2:
///
///   PVAR(tau) = 72 / (M m^4 tau^2) sum_{i=0}^{M-1} A_i^2,
///   A_i = sum_{k=0}^{m-1} ((m-1)/2 - k) (x_{i+k} - x_{i+m+k}),
///
/// with M = N - 2m terms (the count of Vernotte et al. 2020 and AllanTools' pdev), and
/// PDEV(tau0) = OADEV(tau0) at m = 1 (where the weights vanish; Vernotte et al. 2016). O(N)
/// per m: A_{i+1} = A_i - w_0 d_i + w_m d_{i+m} + B_{i+1} and B_{i+1} = B_i - d_i + d_{i+m}
/// with d_j = x_j - x_{j+m}, w_k = (m-1)/2 - k and B_i = sum_{k<m} d_{i+k}, in long double, and
/// A and B formed afresh at the start of every chunk of terms (kernels/allan/detail/chunked.hpp),
/// so that rounding cannot build up over the record and the result does not depend on the
/// thread count. Valid for 2m < N.
StatResult pdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

}  // namespace allanlot::kernels
