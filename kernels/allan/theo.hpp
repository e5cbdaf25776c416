// Thêo1 (Howe & Peppas 2000; NIST SP1065 sec. 5.2.13), the two-sample variance with improved
// confidence and an averaging time up to 75 % of the record.
// Conventions (units, m_list, threads, m < 1) as in kernels/allan/allan.hpp, except:
//  - m is Stable32's "AF": an even averaging factor with 10 <= m <= N - 1 (SP1065 eq. (30));
//    other m give no row, and a record of fewer than 11 points gives an empty result;
//  - tau = 0.75 m tau0 (SP1065 p. 29), the tau at which Thêo1 matches the Allan variance;
//  - gaps: refused (std::invalid_argument), like totdev: every term spans m + 1 points and the
//    normalisation counts them, so a term list with holes has no published meaning.
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Raw (not bias-corrected) Thêo1, NIST SP1065 eq. (30), p. 29:
///
///   Theo1(m) = 1 / (0.75 (N - m) (m tau0)^2) sum_{i=0}^{N-m-1} sum_{d=0}^{m/2-1}
///              [(x_i - x_{i+m/2-d}) + (x_{i+m} - x_{i+m/2+d})]^2 / (m/2 - d)
///
/// n = (N - m) m / 2 terms (Stable32's "#"). This is what Stable32 prints with its bias
/// correction set to white FM (alpha 0, factor 1); other alphas multiply Thêo1 by a constant
/// (Howe & Tasset's Avar/Theo1 ratio) that the caller may apply. Cost O((N - m) m / 2) per m,
/// parallel over chunks of i (kernels/allan/detail/chunked.hpp), so an octave grid up to
/// m = N - 1 costs about N^2 / 2 operations: meant for records up to ~1e5 points or for m
/// lists that stop well before N.
StatResult theo1(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Whether m is a Thêo1 averaging factor for N phase points (even, 10 <= m <= N - 1).
bool theo1_valid(std::int64_t m, std::int64_t n_points);

}  // namespace allanlot::kernels
