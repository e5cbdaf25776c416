// Allan family: Allan, overlapping Allan, modified Allan and time deviation from the
// prefix-summed phase (PhaseData). Every function costs O(N) per averaging factor m.
//
// Conventions shared by every function of this header:
//  - p holds N phase points x_0 .. x_{N-1} (PhaseData), tau0 = p.tau0_s, tau = m tau0;
//  - the deviation is in the channel's rate units (u for rate input; phase units per second
//    for phase input), except TDEV, which is in phase units (u*s for rate input);
//  - m_list may hold any m >= 1 in any order; an m whose estimator has no term (m too large
//    for N, or every term touches a gap) gives no row. The Stable32 limits on m (max_m in
//    stats.hpp) are applied by kernels::compute, not here, so that the NBS14 10-point values
//    can be reproduced;
//  - a term (one squared difference) is left out when any increment inside its span is
//    missing (PhaseData::clean), and `n` counts the terms used;
//  - m < 1 throws std::invalid_argument before any work;
//  - parallel with `nthreads` (0 = OpenMP default) over m and, for small m, over cache tiles
//    of the record (kernels/allan/detail/sweep.hpp); every sum is formed in one fixed order and its
//    pieces are added in index order, so results are bit-identical for any thread count.
#pragma once

// Lets the private kernels/detail headers check that a family header came first.
#define ALLANLOT_KERNELS_FAMILY_HEADER 1

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"
#include "kernels/allan/sum_cache.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// Allan deviation (non-overlapping), NIST SP1065 eq. (7), p. 14, in phase form:
///
///   sigma^2(tau) = 1 / (2 tau^2 n) * sum_{i = 0, m, 2m, ...} (x_{i+2m} - 2 x_{i+m} + x_i)^2
///
/// with n = floor((N-1)/m) - 1 terms for gap-free data.
StatResult adev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Overlapping Allan deviation, NIST SP1065 eq. (11), p. 16:
///
///   sigma^2(tau) = 1 / (2 tau^2 (N - 2m)) * sum_{i=0}^{N-2m-1} (x_{i+2m} - 2 x_{i+m} + x_i)^2
/// With a cache (stats.hpp), sums stored by TOTDEV are reused and new ones stored.
StatResult oadev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0,
                 SumCache* cache = nullptr);

/// Forms OADEV's and OHDEV's sums at every m of m_list in one sweep of the gap-free record and
/// stores both in `cache`, so that oadev, totdev and ohdev with that cache take them from there
/// (the same bits as their own sweeps, for about the cost of OHDEV's alone). Does nothing on a
/// record with gaps (each statistic then tests its own terms).
void prime_second_third(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                        SumCache& cache);

/// Modified Allan deviation, NIST SP1065 eq. (14), p. 17:
///
///   Mod sigma^2(tau) = 1 / (2 m^2 tau^2 (N - 3m + 1))
///                      * sum_{j=0}^{N-3m} ( sum_{i=j}^{j+m-1} (x_{i+2m} - 2 x_{i+m} + x_i) )^2
///
/// The inner sums are third differences of the second-level prefix sum S_k = sum_{i<k} x_i,
/// kept in exact fixed point (see detail::WindowSums for the error analysis).
StatResult mdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Time deviation, NIST SP1065 eq. (16), p. 18: TDEV(tau) = tau / sqrt(3) * MDEV(tau), in
/// phase units (u*s for rate input, the input's own units for phase input).
StatResult tdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// TDEV from an MDEV result of the same data (SP1065 eq. (16)): dev times tau / sqrt(3), rows
/// and n unchanged, confidence fields left empty. tdev() is this of mdev(), so the two agree
/// bit for bit.
StatResult tdev_from_mdev(const StatResult& mdev);

namespace detail {

/// Sum of squared differences and their count: the result of one family core for one m.
struct SumCount {
  double sum = 0.0;
  std::int64_t n = 0;
};

/// Sum of squared second differences (x_{i+2m} - 2 x_{i+m} + x_i)^2 over i = 0, stride,
/// 2 stride, ... and their count, the shared core of ADEV (stride m) and OADEV (stride 1),
/// as allantools' calc_adev_phase(phase, rate, mj, stride). Terms touching a gap are skipped.
SumCount second_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride);

/// The overlapping second-difference sums (stride 1, N - 2m terms) of gap-free data for every
/// m of m_list, by the tiled sweep; those found in `cache` are taken from it, the others
/// computed and stored (cache may be null).
std::vector<SumCount> second_difference_sums(const PhaseData& p,
                                             std::span<const std::int64_t> m_list, int nthreads,
                                             SumCache* cache);

/// Exact fixed-point second-level prefix sums of the phase, the input of the MDEV/TDEV core.
///
/// Why fixed point: the MDEV inner sum is a third difference of S_k = sum_{i<k} x_i, and S
/// grows like max|x| * N (1e4 times larger than x on 5.4 M samples and up to 1e10 times
/// larger than the inner sum at m = 1), so a double S would lose about 10 of its 16 digits in
/// that difference. Instead each x_i is rounded once to an integer X_i = round(x_i * 2^scale_bits)
/// and S_k = sum_{i<k} X_i is kept modulo 2^64. Integer addition is exact and associative, so
///   S_{j+3m} - 3 S_{j+2m} + 3 S_{j+m} - S_j = sum_{i=j}^{j+m-1} (X_{i+2m} - 2 X_{i+m} + X_i)
/// comes out exactly (the wrap-around cancels) whenever its true value fits in int64, which
/// scale_bits guarantees for every m <= m_cap: that value is bounded by 4 m max|X|, and
/// scale_bits makes max|X| <= 2^(60 - ceil(log2(m_cap + 1))).
///
/// Error analysis. The only error is the single rounding of each x_i, |e_i| <= q/2 with
/// q = 2^-scale_bits ~ 2^-(59 - ceil(log2(m_cap + 1))) max|x| (3.6e-12 max|x| for N = 5.4e6,
/// m_cap = N/3); it does not grow with N or m as a floating-point prefix sum's would. An
/// inner sum collects three disjoint windows of m such errors with weights 1, -2, 1: an
/// error of rms q sqrt(m/2), zero-mean and independent of the data, so the summed variance
/// changes by a relative ~ 2 r / sqrt(n) + r^2, r = q sqrt(m/2) / rms(inner sum). For the
/// 1 g accelerometer test (x within ~3e-3 u*s, inner sums >= 1.4e-6 u*s) r <= 1e-8 and the
/// predicted change is ~5e-12 (measured: 7e-12 in the deviation at m = 1, tests/kernels/
/// test_allan_precision.cpp). It would reach 1e-9 only for a phase excursion ~1e7 times the
/// m = 1 second differences (e.g. a large rate ramp over a long record). The other choices cost
/// more: a double-double S doubles the memory traffic and needs ~20 flops per difference,
/// and a running window sum is a serial dependency chain that defeats vectorization.
/// The build is O(N) and, integer addition being associative, bit-identical for any chunking.
struct WindowSums {
  LargeVector<std::uint64_t> s;  // s[k] = sum_{i<k} X_i mod 2^64, k = 0 .. N
  int scale_bits = 0;            // X_i = round(x_i * 2^scale_bits)
  double inv_scale = 1.0;        // 2^-scale_bits
};

/// Builds the window sums of `p` for every m <= m_cap (m_cap >= 1).
WindowSums make_window_sums(const PhaseData& p, std::int64_t m_cap, int nthreads);

/// Sum over j of (inner sum of eq. (14))^2 in phase units squared (not yet divided by m^2),
/// and the number of terms; terms whose span x_j .. x_{j+3m-1} touches a gap are skipped.
SumCount modified_core(const PhaseData& p, const WindowSums& w, std::int64_t m);

}  // namespace detail
}  // namespace allanlot::kernels
