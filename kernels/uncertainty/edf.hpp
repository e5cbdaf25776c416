// Equivalent degrees of freedom (edf) of the Allan-family variance estimators: the number nu for
// which nu * estimate / variance is approximately chi-square distributed (NIST SP1065 sec. 5.3.3).
#pragma once

#include <cstdint>

namespace allanlot::kernels {

/// How a finite-difference variance is built from the phase, in the terms of Greenhall & Riley,
/// "Uncertainty of stability variances based on finite differences", Proc. 35th PTTI (2003),
/// sec. 2: the phase is filtered (F = m for unmodified variances, F = 1 for the modified ones that
/// average m phase points), differenced d times at lag m, and the squared differences are summed
/// with stride m/S (S = 1 non-overlapping, S = m fully overlapping).
struct FiniteDifferenceKind {
  int d = 2;                 // order of the phase difference: 2 Allan family, 3 Hadamard family
  bool overlapping = false;  // stride tau0 (S = m) instead of tau (S = 1)
  bool modified = false;     // phase averaged over m points first (F = 1 instead of F = m)
};

/// Number of terms M = 1 + floor(S (N - L) / m), L = m/F + m d, of the estimator with the given
/// kind at averaging factor m over N phase points (Greenhall & Riley 2003, sec. 3.4); 0 when
/// N < L.
std::int64_t greenhall_terms(FiniteDifferenceKind kind, std::int64_t m, std::int64_t n_phase);

/// Smallest number of phase points for which the estimator has `terms` terms: the inverse of
/// greenhall_terms, used to give gapped data the edf of a contiguous record with as many terms.
std::int64_t greenhall_phase_points(FiniteDifferenceKind kind, std::int64_t m, std::int64_t terms);

/// Greenhall & Riley's combined edf algorithm (Proc. 35th PTTI 2003, sec. 3.4-3.6) for
/// power-law frequency noise S_y ~ f^alpha, alpha in -4..2, with alpha + 2 d > 1 (the variance
/// must converge). It models the phase as the first difference of a continuous-time power-law
/// process, evaluates the autocovariance of the differenced phase (eq. (7)-(9)) and sums it
/// (eq. (10), "BasicSum") when at most J_max = 100 covariance terms are needed; beyond that it
/// uses the paper's large-M asymptotes (Tables 1-3) or the rescaled sum of sec. 3.6. This is the
/// algorithm Stable32 uses for AVAR, OAVAR, MVAR, TVAR, HVAR and OHVAR. Preconditions
/// (std::invalid_argument): m >= 1, d in 1..3, alpha in -4..2 with alpha + 2 d > 1, and at least
/// one term (greenhall_terms > 0).
double edf_greenhall(int alpha, FiniteDifferenceKind kind, std::int64_t m, std::int64_t n_phase);

/// Howe's edf for the total variance TOTVAR, NIST SP1065 sec. 5.3.3, eq. (47) and Table 12:
/// edf = b (T / tau) - c with T / tau = (N - 1) / m for N phase points and (b, c) = (1.50, 0),
/// (1.17, 0.22), (0.93, 0.36) for white, flicker and random-walk FM (alpha = 0, -1, -2).
/// Stable32 1.60 uses these (its TOTDEV bounds on PHASE.DAT match them to 4e-4). Howe's fits
/// cover only those three noises; for alpha = 2, 1 (white and flicker PM) the simple edf of
/// the overlapping Allan variance (SP1065 Table 5, p. 38) is returned, as Stable32 does (its
/// TOTDEV bounds on GPS and time-interval-counter phase, tests/data/stable32/tic/), at least 1.
/// Preconditions: m >= 1, N >= 2, alpha in -2..2.
double edf_totvar(int alpha, std::int64_t m, std::int64_t n_phase);

/// Howe's edf for the modified total variance MTOT (and TTOT, the same estimator scaled),
/// NIST SP1065 sec. 5.3.3, Table 8 (p. 41): edf = b (T / tau) - c with T / tau = (N - 1) / m
/// and (b, c) = (1.90, 2.10), (1.20, 1.40), (1.10, 1.20), (0.85, 0.50), (0.75, 0.31) for
/// alpha = 2, 1, 0, -1, -2; at least 1 (a last-octave m with few windows). Stable32's edf is
/// 1.2 times larger from m = 10 on and MDEV's below (docs/statistics.md); stat_edf uses this
/// from m = 10 on. Preconditions: m >= 1, N >= 2, alpha in -2..2.
double edf_mtotvar(int alpha, std::int64_t m, std::int64_t n_phase);

/// Howe's edf for the Hadamard total variance HTOT (Howe et al., "A total estimator of the
/// Hadamard function used for GPS operations", Proc. 32nd PTTI (2000); the fit of Howe & Tasset's
/// Table I, as Riley, "Confidence intervals and bias corrections for the Stable32 variance
/// functions", gives it): edf = (T / tau) / (b0 + b1 tau / T), T / tau = (N - 1) / m, with
/// (b0, b1) = (0.559, 1.004), (0.868, 1.140), (0.938, 1.696) for alpha = 0, -1, -2; at least 1.
/// The fits are of FM noise at m >= 16 only: stat_edf uses the OHDEV edf below m = 16 and for
/// PM noise (Stable32's edf there is larger and unpublished; docs/statistics.md). On
/// PHASE.DAT at m = 16 Stable32's bounds imply 110.2, this fit 108.7. Preconditions: m >= 1,
/// N >= 2, alpha in -2..0.
double edf_htotvar(int alpha, std::int64_t m, std::int64_t n_phase);

/// Howe & Tasset's empirical edf of Thêo1 ("Thêo1: characterization of very long-term
/// frequency stability", Proc. EFTF 2004, as tabulated in Riley's "Confidence intervals and
/// bias corrections for the Stable32 variance functions"), with r = 0.75 m (Thêo1's tau in units of
/// tau0) and N phase points:
///   alpha  2: 0.86 (N + 1)(N - 4r/3) / (N - r) * r / (r + 1.14)
///   alpha  1: (4.798 N^2 - 6.374 N r + 12.387 r) / (sqrt(r + 36.6) (N - r)) * r / (r + 0.3)
///   alpha  0: ((4.1 N + 0.8) / r - (3.1 N + 6.5) / N) * r^1.5 / (r^1.5 + 5.2)
///   alpha -1: (2 N^2 - 1.3 N r - 3.5 r) / (N r) * r^3 / (r^3 + 2.3)
///   alpha -2: (4.4 N - 2) / (2.9 r) * ((4.4 N - 1)^2 - 8.6 r (4.4 N - 1) + 11.4 r^2)
///             / (4.4 N - 3)^2
/// at least 1 (the random-walk FM fit turns negative near m = N). ThêoH's ThêoBR rows use it
/// too: the bias ratio is a constant factor, which does not change the degrees of freedom.
/// Preconditions: m >= 2, N > m, alpha in -2..2.
double edf_theo1(int alpha, std::int64_t m, std::int64_t n_phase);

/// The edf of the parabolic variance PVAR (Vernotte, Chen & Rubiola, "Response and uncertainty
/// of the parabolic variance PVAR to non-integer exponents of the power law", 2020,
/// arXiv:2005.13631, eqs. (16) and (18)), of the form Vernotte et al. 2016 (IEEE UFFC
/// 63, eq. (24)) derived for white PM:
///   edf = 35 / (A(alpha) m / M - 12 (m / M)^2),  M = N - 2m terms,
///   A(alpha) = 27 + alpha / 4 + 5 alpha^2 / 14 - 3 alpha^3 / 4,
/// valid for m <= N / 4 (PDEV's largest m, stats.hpp max_m). Beyond it (AllanTools' range, up
/// to M = 1) the fit no longer holds and the edf is 1, the conservative floor. At m = 1 PVAR
/// is the overlapping Allan variance and stat_edf takes OADEV's edf. Preconditions: m >= 1,
/// N > 2m, alpha in -2..2.
double edf_pvar(int alpha, std::int64_t m, std::int64_t n_phase);

/// Stable32's bias factor of the Hadamard total variance (Riley, "Confidence intervals and
/// bias corrections for the Stable32 variance functions", Hamilton Technical Services): the
/// expected HTOT / HVAR ratio, 0.995, 0.851 and 0.771 for alpha = 0, -1 and -2, and 1 for
/// PM noise (alpha 1, 2), where Stable32 corrects nothing. The corrected deviation is the raw
/// one divided by the square root.
double htotvar_bias(int alpha);

}  // namespace allanlot::kernels
