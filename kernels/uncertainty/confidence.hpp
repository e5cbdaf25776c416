// Confidence intervals of the Allan-family deviations, as Stable32 1.60 computes them: noise
// identification per tau (kernels/uncertainty/noise_id.hpp), the equivalent degrees of freedom of
// the statistic for that noise (kernels/uncertainty/edf.hpp) and chi-square bounds
// (kernels/uncertainty/chi2.hpp).
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/edf.hpp"
#include "kernels/uncertainty/noise_id.hpp"

#include <cstdint>

namespace allanlot::kernels {

/// Default confidence of the intervals: Stable32's "Confidence Factor = 0.683" (1 sigma).
inline constexpr double kDefaultConfidence = 0.683;

/// Chi-square interval of a deviation with `edf` degrees of freedom at confidence c
/// (SP1065 sec. 5.3.3, eq. (45)): the variance estimate times edf / sigma^2 is chi-square with
/// edf degrees of freedom, so
///   lo = dev sqrt(edf / chi2_{(1+c)/2}(edf)),  hi = dev sqrt(edf / chi2_{(1-c)/2}(edf)),
/// with chi2_p the p-quantile; lo < hi for any edf > 0 and 0 < c < 1 (the larger quantile gives
/// the lower bound; AllanTools issue #118 had the two swapped), and lo < dev < hi at the usual
/// confidences (at a very small c both quantiles lie on the same side of edf).
/// Throws std::invalid_argument for c outside (0, 1) or edf <= 0.
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
};
Interval chi2_interval(double dev, double edf, double confidence);

/// How statistic s is built, for edf_greenhall: its StatInfo::differences (the table of
/// kernels/allan/stats.cpp), d = 2 (Allan) or 3 (Hadamard), overlapping or not, modified or not
/// (Greenhall & Riley 2003, sec. 2). Throws std::invalid_argument for a statistic whose
/// EdfModel is not Greenhall (its edf is another fit).
FiniteDifferenceKind difference_kind(Stat s);

/// The edf Stable32 1.60 uses for statistic s at averaging factor m with noise alpha, over N
/// phase points with `terms` terms in the estimator, by the statistic's EdfModel
/// (kernels/allan/stats.hpp StatInfo::edf):
///  - Greenhall: Greenhall & Riley's combined algorithm (edf_greenhall) with the statistic's
///    Differences; Stable32's bounds on PHASE.DAT match it within 4e-4, while the simple
///    SP1065 Table 5 formula for white FM (edf = (3(N-1)/(2m) - 2(N-2)/N) 4m^2/(4m^2+5)) gives
///    666 instead of Stable32's 782 at m = 1;
///  - Totvar: Howe's b (T/tau) - c (edf_totvar);
///  - Mtotvar: the modified Allan edf below m = 10 (where Stable32's bounds imply it), SP1065
///    Table 8 (edf_mtotvar) from m = 10 on;
///  - Htotvar: Howe's fit (edf_htotvar) for FM noise at m >= 16, else the overlapping Hadamard
///    edf;
///  - Theo1: Howe & Tasset's fits (edf_theo1); Theoh: the overlapping Allan edf on its OADEV
///    rows (m < floor(0.1 (N - 1))), edf_theo1 on its ThêoBR rows;
///  - Pvar: Vernotte et al.'s fit (edf_pvar), the overlapping Allan edf at m = 1;
///  - None: NaN (no interval, stats.hpp has_interval).
/// Gaps: when `terms` is below the count of a contiguous record of N points, the edf is that
/// of the shortest contiguous record with `terms` terms (greenhall_phase_points), i.e. the
/// missing terms are treated as a shorter record. This is exact for a gap at either end and
/// slightly pessimistic for a gap in the middle (the two pieces' terms are independent of
/// each other, which can only add degrees of freedom).
/// Filled samples (`n_filled` = F, kernels/allan/gaps.hpp): an interpolated sample is an
/// estimate from its neighbours and carries no information of its own, so the row is given
/// the edf of a record with F fewer points. For the finite-difference variances the terms are
/// reduced by those F points give, G(N) - G(N - F) (greenhall_terms; at least 1 term left),
/// and the shorter-record rule above applies to what remains, so the correlation of the
/// overlapping terms stays in Greenhall & Riley's sum; the other models' edf, fits proportional
/// to the record length T / tau (b (T / tau) - c), is scaled by
/// (N - F) / N. F = 0 changes nothing. Throws std::invalid_argument unless 0 <= F < N.
double stat_edf(Stat s, int alpha, std::int64_t m, std::int64_t n_phase, std::int64_t terms,
                std::int64_t n_filled = 0);

/// Fills r.edf, r.dev_lo, r.dev_hi, r.alpha (one entry per row) and r.confidence for the rows
/// of `r`, the result of statistic s on p (kernels::compute), at the given two-sided
/// confidence. alpha comes from identify_alpha, edf from stat_edf (p.n_filled its filled
/// samples), the bounds from chi2_interval. Rows with dev = 0 get edf and alpha but
/// lo = hi = 0. A statistic without an interval (has_interval false: MTIE, TIE rms) gets its alpha
/// and NaN edf, lo and hi. For HTOTDEV it also applies Stable32's bias correction to r.dev (divided
/// by sqrt(htotvar_bias(alpha)) at m > 1, edf.hpp) before the bounds are taken. Parallel over rows
/// with `nthreads` (0 = OpenMP default); each row is written by one thread in a fixed order, so the
/// output is bit-identical for any thread count. Throws std::invalid_argument for confidence
/// outside (0, 1) or rows that are not a result of s on p (unequal lengths, m not increasing).
/// `cache` (optional, see noise_id.hpp) shares the noise identification between the statistics of
/// one record; it changes no result.
void add_confidence(Stat s, const PhaseData& p, StatResult& r,
                    double confidence = kDefaultConfidence, int nthreads = 0,
                    Lag1Cache* cache = nullptr);

}  // namespace allanlot::kernels
