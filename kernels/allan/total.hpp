// Total family: total deviation (TOTDEV) from the phase, extended by double reflection.
// Conventions (units, m_list, threads) as in kernels/allan/allan.hpp, except for gaps (below).
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"
#include "kernels/allan/sum_cache.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Total deviation, NIST SP1065 eq. (25), p. 23, the doubly reflected TOTVAR (SP1065 p. 108
/// note to the NBS14 table):
///
///   Tot var(tau) = 1 / (2 tau^2 (N - 2)) * sum_{i=1}^{N-2} (x*_{i-m} - 2 x*_i + x*_{i+m})^2
///
/// with x*_k = x_k inside the record and, outside it, the record reflected about each end
/// point: x*_{-j} = 2 x_0 - x_j and x*_{N-1+j} = 2 x_{N-1} - x_{N-1-j} (0-based indices,
/// SP1065's x_{1-j} and x_{N+j}). n = N - 2 for every m. Stable32 stops at m = (N-1)/2
/// (compute()'s default range), where each centre reflects at most one end; AllanTools goes on
/// to m = N - 1, where a centre may reflect both, and so does this function with `beyond_half`
/// (MRange::Estimable). A larger m gives no row.
/// The reflection is odd about the end points, so a linear phase (constant rate) stays
/// linear and the removed mean rate of PhaseData does not change the result.
///
/// Gaps: throws std::invalid_argument when p has gaps. The reflection makes every term near an
/// end depend on the end point and on a mirrored sample, and the sum's normalisation N - 2 is
/// fixed by the record length, so "leave out the terms that touch a gap" has no definition
/// that keeps TOTVAR's meaning (Stable32 fills gaps before a total variance instead); an error
/// is better than a number of unknown meaning.
StatResult totdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0,
                  SumCache* cache = nullptr, bool beyond_half = false);

namespace detail {

/// Sum of the N - 2 squared reflected second differences of eq. (25) for one m, and N - 2.
/// Preconditions: no gaps, 1 <= m <= (N-1)/2.
SumCount total_core(const PhaseData& p, std::int64_t m);

}  // namespace detail
}  // namespace allanlot::kernels
