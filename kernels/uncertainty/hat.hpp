// Statistics of clocks measured in pairs, with their confidence intervals: the three-cornered
// hat (each clock's Allan deviation from the three pairwise records of three clocks) and the
// Groslambert codeviation with its interval (docs/statistics.md "Two recordings: gcodev and the
// three-cornered hat"). Both combine overlapping Allan variances (and the codeviation) of the
// pair records, so their uncertainty comes from the pairs' edf (edf.hpp, Greenhall & Riley).
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace allanlot::kernels {

/// Variance of the three-cornered-hat estimate of clock A's Allan variance,
/// A = (s_ab + s_ca - s_bc) / 2, from the pairs' overlapping Allan variances s and their edf nu.
///
/// Derivation (the moment matching of Satterthwaite 1946 that GUM G.4 uses, here with the
/// covariances the shared clocks cause; the reduced-degrees-of-freedom approach of Ekstrom &
/// Koppang, "Error bars for three-cornered hats", Proc. IEEE IFCS 2002, pp. 721-724,
/// doi:10.1109/FREQ.2002.1075975). With independent Gaussian clocks, a pair's estimate has
/// var(s_xy) = 2 s_xy^2 / nu_xy (the chi-square model of SP1065 sec. 5.3.3), and two pairs that
/// share clock x are correlated through it alone: by Isserlis' theorem the covariance of the
/// squared second differences of (x - y) and (z - x) is 2 x^2, so
/// cov(s_xy, s_zx) = 2 x^2 / sqrt(nu_xy nu_zx), x the shared clock's variance (the hat's own
/// estimate; only its square enters). Then
///   var(A) = [var(s_ab) + var(s_ca) + var(s_bc)
///             + 2 cov(s_ab, s_ca) - 2 cov(s_ab, s_bc) - 2 cov(s_ca, s_bc)] / 4,
/// which for equal nu is (2 A^2 + A B + A C + B C) / nu: nu's chi-square variance 2 A^2 / nu
/// when the other clocks are silent, and larger as they grow. Exact for Gaussian clocks of one
/// noise type (the terms' correlations then scale alike in every pair, and one nu describes
/// them all); with different types, sqrt(nu_xy nu_zx) is a stand-in. Clocks B and C by
/// rotation.
double hat_estimate_variance(double s_ab, double s_bc, double s_ca, double nu_ab, double nu_bc,
                             double nu_ca);

/// Equivalent degrees of freedom of the Groslambert covariance g of records x and y with
/// overlapping Allan variances s_x, s_y of edf nu_x, nu_y (same moment matching): by Isserlis'
/// theorem var(g) = (s_x s_y + g^2) / sqrt(nu_x nu_y), and edf = 2 g^2 / var(g), which is nu
/// when x = y (then g = s_x) and falls to 0 as the records decorrelate. 0 when g = 0.
double codev_edf(double s_x, double s_y, double g, double nu_x, double nu_y);

/// The three-cornered hat of three clocks A, B, C from the records of their pairwise phase
/// (or rate) differences AB, BC, CA (the sign of each difference does not matter).
struct HatResult {
  /// Overlapping Allan deviation of AB, BC, CA with add_confidence's edf, interval and alpha.
  std::array<StatResult, 3> pair;
  /// Clocks A, B, C: per tau, the variance estimate v = (s_ab + s_ca - s_bc) / 2 (rotated for B
  /// and C; Gray & Allan, "A method for estimating the frequency stability of an individual
  /// oscillator", Proc. 28th FCS 1974, eq. (4), the method NIST SP1065 calls the
  /// three-cornered hat) as a signed deviation
  /// dev = sign(v) sqrt(|v|); edf = 2 v^2 / hat_estimate_variance; dev_lo, dev_hi the
  /// chi-square interval of SP1065 eq. (45) with that edf; n the fewest terms of the three
  /// pairs; alpha the redder (smaller) alpha of the two pairs that contain the clock. Where
  /// v <= 0 (the clock is quieter than the scatter of the others can resolve, or the clocks are
  /// correlated), dev is -sqrt(|v|) (0 for v = 0) and edf, dev_lo, dev_hi are NaN: a variance
  /// interval has no meaning there.
  std::array<StatResult, 3> clock;
  /// Per clock: the taus where v <= 0, in words; empty when none.
  std::array<std::string, 3> notes;
};

/// Computes the hat at every m of m_list up to max_m(Stat::Oadev, N) (larger m give no row);
/// a tau where any pair has no term gives no clock row. Preconditions (std::invalid_argument):
/// the three records have the same number of phase points and tau0_s; m >= 1; confidence in
/// (0, 1). Parallel inside the OADEV and confidence kernels with `nthreads`; bit-identical for
/// any thread count.
HatResult three_cornered_hat(const PhaseData& ab, const PhaseData& bc, const PhaseData& ca,
                             std::span<const std::int64_t> m_list, double confidence,
                             int nthreads = 0);

/// The N-cornered hat (N >= 3 clocks) from the N(N-1)/2 records of their pairwise differences,
/// in pair order: (0,1), (0,2), ..., (0,N-1), (1,2), ..., (N-2,N-1) (for A, B, C, D: AB AC AD
/// BC BD CD). Index of pair (i, j), i < j, in that order.
std::size_t hat_pair_index(std::size_t i, std::size_t j, std::size_t n_clocks);

/// Weight w_p of pair p in clock i's variance estimate v_i = sum_p w_p s_p: the Gray-Allan
/// least-squares solution of s_jk = v_j + v_k (independent clocks) for the N variances,
/// v = (A^T A)^-1 A^T s with A the pairs' 0/1 design matrix; A^T A = (N - 2) I + J, so
///   v_i = [sum_{j != i} s_ij - sum_{j<k} s_jk / (N - 1)] / (N - 2),
/// the solution for N oscillators of Gray & Allan (Proc. 28th FCS 1974, the paper of
/// HatResult's three-cornered hat; Riley, NIST SP1065, its three-cornered-hat section, gives
/// the same sums). w_p = (1 - 1 / (N - 1)) / (N - 2) for a pair with clock i, -1 / ((N - 1)(N - 2))
/// otherwise; for N = 3 it is the three-cornered hat (1/2, 1/2, -1/2).
std::vector<double> hat_weights(std::size_t clock, std::size_t n_clocks);

/// Variance of clock i's estimate v_i = sum_p w_p s_p from the pairs' variances s and edf nu
/// (pair order) and the clocks' variance estimates v, propagated through the pairs'
/// covariances: var(s_p) = 2 s_p^2 / nu_p, cov(s_p, s_q) = 2 v_k^2 / sqrt(nu_p nu_q) for two
/// pairs that share clock k (Isserlis, as hat_estimate_variance), 0 for disjoint pairs; then
/// var(v_i) = sum_p sum_q w_p w_q cov(s_p, s_q). For N = 3 it is hat_estimate_variance.
double n_hat_estimate_variance(std::span<const double> s, std::span<const double> nu,
                               std::span<const double> v, std::size_t clock, std::size_t n_clocks);

/// The N-cornered hat's result: the pairs' OADEV (pair order) and each clock's deviation.
struct NHatResult {
  /// Overlapping Allan deviation of each pair with add_confidence's edf, interval and alpha.
  std::vector<StatResult> pair;
  /// Per clock and tau: v = sum_p w_p s_p (hat_weights) as a signed deviation
  /// dev = sign(v) sqrt(|v|); edf = 2 v^2 / n_hat_estimate_variance (Satterthwaite's moment
  /// matching, as HatResult); dev_lo, dev_hi the chi-square interval of SP1065 eq. (45) with
  /// that edf; n the fewest terms of all pairs; alpha the smallest of the pairs with the clock.
  /// Where v <= 0, dev is -sqrt(|v|) (not clipped) and edf, dev_lo, dev_hi are NaN.
  std::vector<StatResult> clock;
  /// Per clock: the taus where v <= 0, in words, without the clock's name (the caller names
  /// the clocks); empty when none.
  std::vector<std::string> notes;
};

/// Computes the N-cornered hat of n_clocks = N >= 3 clocks from the N(N-1)/2 pair records in
/// pair order (hat_pair_index), at every m of m_list up to max_m(Stat::Oadev, points); a tau
/// where any pair has no term gives no clock row. Preconditions (std::invalid_argument): N >= 3,
/// pairs.size() == N(N-1)/2, equal lengths and tau0_s, m >= 1, confidence in (0, 1).
/// Bit-identical for any thread count. For N = 3 (pairs AB AC BC) the clocks agree with
/// three_cornered_hat(AB, BC, CA) to rounding (the sign of a difference does not matter).
NHatResult n_cornered_hat(std::span<const PhaseData> pairs, std::size_t n_clocks,
                          std::span<const std::int64_t> m_list, double confidence,
                          int nthreads = 0);

/// The Groslambert codeviation of x and y with its interval, and the two records' OADEV.
struct CodevResult {
  /// gcodev (kernels/allan/codev.hpp): signed dev; edf = codev_edf with the records' OADEV
  /// edf; dev_lo, dev_hi the chi-square interval of |dev| with that edf, given dev's sign (so
  /// dev_lo <= dev <= dev_hi also for negative dev); NaN where dev = 0; alpha the redder of the
  /// two records' alpha.
  StatResult codev;
  std::array<StatResult, 2> oadev;  // x and y, with add_confidence
};

/// Computes gcodev with its interval at every m of m_list up to max_m(Stat::Oadev, N).
/// Preconditions as gcodev and confidence in (0, 1).
CodevResult gcodev_with_confidence(const PhaseData& x, const PhaseData& y,
                                   std::span<const std::int64_t> m_list, double confidence,
                                   int nthreads = 0);

}  // namespace allanlot::kernels
