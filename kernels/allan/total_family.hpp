// The modified, time and Hadamard total deviations (NIST SP1065 secs. 5.2.12-5.2.14): each
// averages, over every window of 3m points, a statistic of the window after its half-average
// frequency (MTOT, TTOT) or drift (HTOT) is removed and it is extended by uninverted even
// reflection to 9m points. Conventions (units, m_list, threads, m < 1) as in
// kernels/allan/allan.hpp, except:
//  - gaps: refused with std::invalid_argument, like totdev (kernels/allan/total.hpp): the
//    windows and their reflections have no published meaning across a gap;
//  - cost: O(m) per window, O((N - 3m) m) per m (below), parallel over chunks of windows
//    (kernels/allan/detail/chunked.hpp).
//
// Why O(m) per window: the 6m terms of a window's reflected sequence are third differences of
// its prefix sums at lag m, and the reflection makes them a quadratic form of the window that is
// not shift-invariant (a Toeplitz plus a Hankel part), so no running sum carries one window's
// total to the next. Each window's prefix sums are formed afresh (window-local, so the
// cancellation is that of the window, not of the record), its half averages and detrend come
// from them in O(1), and the 6m terms read them in O(1) each.
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Modified total deviation, SP1065 eq. (27), p. 25 (Howe & Vernotte 1999): over the
/// M = N - 3m + 1 windows x_n .. x_{n+3m-1} of the phase, with the linear phase trend of the
/// half averages removed (slope = difference of the means of the first and last floor(3m/2)
/// points over the distance of their centres) and the window reflected to
/// x*_{-3m..6m-1} = (reversed, window, reversed),
///
///   Mod Totvar(tau) = 1 / (2 tau^2 M) sum_n (1 / 6m) sum_{j=-3m}^{3m-1} z_j^2,
///   z_j = (1/m) sum_{k=j}^{j+m-1} (x*_k - 2 x*_{k+m} + x*_{k+2m}),
///
/// n = M (Stable32's "#"). Valid for 3m <= N. No bias correction (Stable32 1.60 applies none:
/// its PHASE.DAT tables with alpha 0 and 1 print the same deviations).
StatResult mtotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Time total deviation, SP1065 eq. (28), p. 26, in its corrected form:
/// TTOT(tau) = tau / sqrt(3) * MTOT(tau) (SP1065 prints tau^3 in the variance; Stable32 and
/// AllanTools use tau^2, as the time deviation does). In phase units; n as mtotdev.
StatResult ttotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// Hadamard total deviation, SP1065 eq. (29), p. 27 (Howe et al. 2001), without bias correction:
/// over the M = N - 3m windows of 3m frequency averages y_i = (x_{i+1} - x_i) / tau0 with their
/// half-average drift removed and reflected as above,
///
///   Htotvar(tau) = 1 / (6 M) sum_n (1 / 6m) sum_{j=-3m}^{3m-1} z_j^2,
///   z_j = (1/m) sum_{k=j}^{j+m-1} (y*_k - 2 y*_{k+m} + y*_{k+2m}),
///
/// and at m = 1 the overlapping Hadamard deviation (SP1065 p. 27, Stable32), n = N - 3 there.
/// Stable32's bias correction (divide the variance by 0.995, 0.851, 0.771 for alpha = 0, -1,
/// -2; none for PM noise) needs the noise type and is applied by kernels::add_confidence
/// (kernels/uncertainty/confidence.hpp); this function returns the uncorrected value.
StatResult htotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

}  // namespace allanlot::kernels
