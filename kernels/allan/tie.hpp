// Time-error statistics: MTIE and TIE rms (ITU-T G.810, NIST SP1065 secs. 5.2.15-5.2.16).
// Conventions (m_list, threads, m < 1) as in kernels/allan/allan.hpp, except:
//  - the result is a time (phase) error in phase units (u*s for rate input), not a deviation
//    of the rate, and it is taken of the phase *with* its frequency offset: PhaseData removes
//    the mean rate (which no Allan-family statistic sees), but a constant frequency offset is
//    a real time error, and Stable32's MTIE and TIE rms tables of PHASE.DAT are those of the
//    phase as recorded. The kernels add p.mean_rate back, x_k + k tau0 mean_rate, term by term;
//  - gaps are supported: a window or pair that touches a gap is left out, n counts the rest.
#pragma once

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Maximum time interval error, ITU-T G.810 eq. (II.4), SP1065 sec. 5.2.15, p. 32:
///
///   MTIE(tau) = max_{i = 0 .. N-1-m} ( max_{i<=k<=i+m} x_k - min_{i<=k<=i+m} x_k )
///
/// over the n = N - m windows of m + 1 points (Stable32's "#"). O(N) per m: the window maximum
/// and minimum are kept in monotone deques (each index enters and leaves each deque once).
StatResult mtie(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

/// TIE rms, SP1065 sec. 5.2.16, p. 33: sqrt( sum_{i=0}^{n-1} (x_{i+m} - x_i)^2 / n ) over the
/// n = N - m pairs; O(N) per m.
StatResult tierms(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads = 0);

}  // namespace allanlot::kernels
