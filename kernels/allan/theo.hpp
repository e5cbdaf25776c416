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
/// lists that stop well before N. `m_min` is the smallest m evaluated: 10 as SP1065 and
/// Stable32 (the default), 2 for AllanTools' range (the formula holds for any even m >= 2).
StatResult theo1(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0,
                 std::int64_t m_min = 10);

/// Whether m is a Thêo1 averaging factor for N phase points (even, m_min <= m <= N - 1).
bool theo1_valid(std::int64_t m, std::int64_t n_points, std::int64_t m_min = 10);

/// ThêoH, the hybrid of Howe & Tasset ("ThêoH: a hybrid, high-confidence statistic that
/// improves on the Allan deviation", Metrologia 43 (2006); SP1065 sec. 5.2.14 and eqs. (31)-(32),
/// pp. 30-31), as variances:
///
///   ThêoBR(m) = [1/(n+1) sum_{i=0}^{n} OAVAR(9 + 3i) / Theo1(12 + 4i)] Theo1(m),
///   n = floor(0.1 N / 3 - 3)   (each ratio at the same tau: 0.75 (12 + 4i) = 9 + 3i),
///   ThêoH(m) = OAVAR(m) at tau = m tau0 for 1 <= m < k, and ThêoBR(m) at tau = 0.75 m tau0
///   for the Thêo1 m (even, 10 <= m <= N - 1) with 0.75 m >= k,
///
/// where k tau0 is the largest tau <= 10 % of the record, k = floor(0.1 (N - 1)). So m is the
/// OADEV averaging factor below k and Thêo1's "AF" above it; an m of m_list in neither range
/// gives no row; n is the OADEV or Thêo1 term count of the row. Records with n < 0 (N < 90)
/// give an empty result. The bias ratio costs n + 1 Thêo1 evaluations, about N^3 / 900
/// operations (1e6 for N = 1001, 1e10 for N = 2e4): meant for clock records up to ~2e4 points.
/// Gaps: refused, as theo1.
StatResult theoh(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

}  // namespace allanlot::kernels
