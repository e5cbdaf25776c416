// Power-law noise identification per averaging time, as Stable32 1.60 does it: the lag-1
// autocorrelation method of Riley & Greenhall when enough averaged points exist, the B1 ratio
// (with R(n) for the modified variances) otherwise. The result is the integer alpha of the
// rate/frequency spectrum S_y(f) ~ f^alpha, in -2..2.
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"

#include <cstdint>
#include <map>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

namespace allanlot::kernels {

/// Lag-1 autocorrelation of a series as Stable32 computes it: with zbar the mean of the finite
/// values, r1 = (n-1)/n * sum_t (z_t - zbar)(z_{t+1} - zbar) / sum_t (z_t - zbar)^2 over the n
/// finite values (products over consecutive finite pairs only; NaN marks a missing value).
/// The factor (n-1)/n is not in Riley & Greenhall's eq. (2); it is what Stable32 applies: the
/// pink_frequency tables decide it (at m = 218 and 280 the unscaled r1 gives delta = -0.257 and
/// -0.254, i.e. alpha 1, where Stable32 prints 0; scaled, delta = -0.2498 and -0.2446).
/// Returns 0 for fewer than 2 finite values or a constant series.
double lag1_autocorrelation(std::span<const double> z);

/// Outcome of the lag-1 method at one averaging factor.
struct Lag1Estimate {
  double delta = 0.0;  // r1 / (1 + r1) of the last differenced series
  int d = 0;           // number of differences taken of the decimated phase
  int alpha = 0;       // -round(2 delta) - 2 d + 2, clamped to -2..2
};

/// Riley & Greenhall, "Power law noise identification using the lag 1 autocorrelation",
/// Proc. 18th EFTF (2004), sec. 3 (also SP1065 sec. 5.6.4): decimate the phase by m
/// (z_k = x_{k m}), then difference it d = 0, 1, ... times until delta = r1/(1+r1) < 0.25 or
/// d = dmax; p = -round(2 delta) - 2 d is the phase-spectrum exponent and alpha = p + 2
/// (rounding halves away from zero). dmax is 2 for the Allan and total families, 3 for the
/// Hadamard family (the d of the statistic, as in the paper). Starting from the phase also
/// covers rate input: the first difference of the decimated phase is exactly the series of
/// m-sample rate averages that Stable32 starts from for frequency data. A difference across a
/// gap (PhaseData::gaps) is missing (NaN) and drops out of the autocorrelation.
/// Preconditions: m >= 1, dmax >= 1, at least 2 decimated points.
Lag1Estimate noise_id_lag1(const PhaseData& p, std::int64_t m, int dmax);

/// The lag-1 estimates of one phase record, shared between the statistics computed on it:
/// noise_id_lag1 depends only on (m, dmax), and the differencing levels of dmax 2 are the first
/// levels of dmax 3, so the cache keeps each m's deltas per level and the Allan and total
/// family (dmax 2) and the Hadamard family (dmax 3) share one run per m (it was a third of a
/// channel's time in `analyze` with the six default statistics). Thread-safe; a
/// value computed twice by two threads is the same value, so results do not depend on the
/// thread count. Valid for one PhaseData only (the caller keeps one cache per record).
class Lag1Cache {
public:
  Lag1Estimate get(const PhaseData& p, std::int64_t m, int dmax);
  /// Computes the estimates of every m of `ms` not yet held for dmax in one multi-m sweep
  /// over a gap-free record (two sweeps per differencing level for all m together, instead
  /// of two passes per m); same values as get(). Does nothing for gapped records or dmax > 3.
  /// With nthreads > 1 (0 = OpenMP default) the m are shared out, one sweep per thread; the
  /// values do not depend on the thread count.
  void prefetch(const PhaseData& p, std::span<const std::int64_t> ms, int dmax, int nthreads = 1);

private:
  std::mutex mutex_;
  std::map<std::int64_t, std::vector<double>> deltas_;  // m -> delta at levels 0, 1, ...
};

/// Barnes' bias function B1(N, r = 1, mu): the expected ratio of the N-sample variance to the
/// two-sample (Allan) variance for phase noise exponent mu (sigma^2(tau) ~ tau^mu),
/// B1 = N (1 - N^mu) / (2 (N - 1) (1 - 2^mu)), with the limit N ln N / (2 (N - 1) ln 2) at
/// mu = 0 (Barnes, NBS TN 375 (1969); Howe et al., Proc. 32nd PTTI (2000), Table 3).
double b1_expected(double n, int mu);

/// Noise type from a measured B1 ratio over n samples: mu is tested downwards from 1 (random
/// walk FM) and chosen at the first boundary the ratio exceeds, the boundaries being the
/// geometric means of adjacent expected values (SP1065 sec. 5.6.2). Returns alpha =
/// -mu - 1 in -2..0, or 1 for mu = -2, where B1 cannot tell white from flicker PM.
int alpha_from_b1(double b1, double n);

/// Expected R(n) = MVAR / AVAR for flicker PM (alpha = 1, with the measurement bandwidth at the
/// Nyquist frequency 1 / (2 tau0)) and white PM (alpha = 2): 3.37 / (1.04 + 3 ln(pi m)) and
/// 1 / m (NIST TN 1337, Table A-2 ratio of the mod. and normal Allan variances).
double rn_expected(std::int64_t m, int alpha);

/// Flicker (1) or white (2) PM from a measured R(n) at averaging factor m: the boundary is the
/// geometric mean of the two expected values.
int alpha_from_rn(double rn, std::int64_t m);

/// Identified alpha for every row of `r` (statistic s computed on p), in Stable32's way:
///  - lag-1 method (noise_id_lag1, dmax the statistic's StatInfo::noise_id_dmax) when at least 30
///  m-sample
///    averages exist (floor((N - 1) / m) >= 30, Stable32's documented threshold);
///  - otherwise the B1 ratio s^2 / AVAR(m): s^2 the sample variance (n - 1 denominator) of the
///    non-overlapping m-sample rate averages, AVAR the non-overlapping Allan variance at m
///    (also for Totdev), compared with b1_expected for N = r.n (the statistic's
///    number of terms); for Mdev and Tdev a B1 verdict of PM noise is refined by R(n) =
///    MVAR / OAVAR (Stable32 manual, "Noise identification");
///  - for m beyond half of max_m(s, N) (stats.hpp: Stable32's largest m, i.e. the last octave of
///    a Stable32 run) the alpha of the previous (smaller) m of the list is kept. Stable32 does not
///    document this; its tables show it: on PHASE.DAT (white FM) ADEV prints alpha 1 for every m in
///    101..197 although the B1 ratio gives 0 at m = 105, 115..121, 149, 158.., and OADEV's octave
///    run prints 0 at m = 128 (kept from m = 64) where the all-tau run prints 1 (kept from m =
///    125).
/// Rows are taken in increasing m, as stats::compute returns them. Gaps: the averages and
/// differences that touch a gap are left out. Parallel over rows with `nthreads`; the result
/// does not depend on the thread count.
/// `cache` (optional) shares the lag-1 estimates with other statistics of the same record.
std::vector<int> identify_alpha(Stat s, const PhaseData& p, const StatResult& r, int nthreads = 0,
                                Lag1Cache* cache = nullptr);

}  // namespace allanlot::kernels
