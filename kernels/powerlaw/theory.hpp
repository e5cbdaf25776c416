// The Allan and modified Allan variances of the power-law noise types (NIST SP1065 sec. 5.2.4
// p. 38 and sec. 5.2.5 p. 39 with Table 5; the ratio R(n) = MVAR / AVAR of sec. 5.2.5), for a
// level h_alpha = 1 of the one-sided PSD S_y(f) = h_alpha f^alpha of the fractional frequency:
//
//   alpha  noise           AVAR(tau)                                MVAR(tau)
//    2     white PM        3 f_h / (4 pi^2 tau^2)                   3 f_h tau0 / (4 pi^2 tau^3)
//    1     flicker PM      [1.038 + 3 ln(2 pi f_h tau)] / (4 pi^2 tau^2)   3.37 / (4 pi^2 tau^2)
//    0     white FM        1 / (2 tau)                              1 / (4 tau) (large m)
//   -1     flicker FM      2 ln 2                                   (27/20) ln 2
//   -2     random-walk FM  (2 pi^2 / 3) tau                         (11 pi^2 / 20) tau
//
// with f_h = 1 / (2 tau0), the Nyquist frequency of samples at interval tau0 (white PM's
// variance is that of the phase samples, h_2 f_h / (4 pi^2)). The AVAR column is exact for
// white PM, white FM (samples that are interval means, as kernels/simulate/simulate.hpp and a
// counter deliver them) and the continuous-time random-walk and flicker FM. The MVAR column is
// exact for white PM (the three sums of the modified second difference have disjoint samples:
// MVAR = AVAR / m) and, through white_fm_mvar's exact sum, for white FM at every m; flicker PM,
// flicker FM and random-walk FM use SP1065's large-m values (R(n) reaches them within a few per
// cent by m = 8).
#pragma once

#include <cstdint>

namespace allanlot::kernels::powerlaw {

/// eq. (3)'s squared coefficients of the noise types it shares with the power-law model, in
/// the rate's units and seconds (kernels/simulate/simulate.hpp; equal Allan variances at every
/// tau): white PM is eq. (3)'s Q (Q^2 = h_2 f_h / (4 pi^2), the variance of the phase samples),
/// white FM its N (N^2 = h_0 / 2), flicker FM its B (B^2 = pi h_-1), random-walk FM its K
/// (K^2 = 2 pi^2 h_-2). Flicker PM has no eq. (3) term.
struct Eq3Squares {
  double q2 = 0, n2 = 0, b2 = 0, k2 = 0;
};
Eq3Squares eq3_squares(double h2, double h0, double hm1, double hm2, double tau0_s);

/// AVAR at tau_s = m tau0_s of the noise type alpha (-2..2) at level h_alpha = 1 (table above).
/// Throws std::invalid_argument for alpha outside -2..2, tau_s or tau0_s not > 0.
double avar_per_h(int alpha, double tau_s, double tau0_s);

/// MVAR at tau_s = m tau0_s (m >= 1) of the noise type alpha at level h_alpha = 1 (table above;
/// white FM exact at every m). Throws like avar_per_h.
double mvar_per_h(int alpha, double tau_s, double tau0_s);

/// MVAR of white FM of level h_0 = 1 at averaging factor m, exact for interval-mean samples of
/// variance 1 / (2 tau0): the modified second difference sum_{i<m} (x_{i+2m} - 2 x_{i+m} + x_i)
/// of the phase x = tau0 cumsum(y) weights y_j by tau0 c_j, c_j = A_j - B_j (A_j, B_j the numbers
/// of i in [0, m) for which y_j lies in the later or the earlier window), so
/// MVAR = sum_j c_j^2 / (2 m^2 tau^2) * tau0^2 / (2 tau0) (SP1065 eq. (14)); O(m).
double white_fm_mvar(std::int64_t m, double tau0_s);

}  // namespace allanlot::kernels::powerlaw
