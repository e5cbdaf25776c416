// Chi-square distribution for non-integer degrees of freedom: the regularized incomplete gamma
// function and its inverse, which turn an equivalent number of degrees of freedom (edf) into
// confidence bounds (NIST SP1065 sec. 5.3.3, eq. (43)-(45)); and the digamma and trigamma
// functions, the exact mean and variance of the logarithm of a chi-square variate.
#pragma once

namespace allanlot::kernels {

/// Regularized lower incomplete gamma function P(a, x) = gamma(a, x) / Gamma(a), for a > 0 and
/// x >= 0. Series expansion for x < a + 1, Legendre's continued fraction (modified Lentz
/// evaluation) otherwise, as recommended by Abramowitz & Stegun 6.5.29 and 6.5.31; relative
/// accuracy about 1e-15. Throws std::invalid_argument for a <= 0, x < 0 or NaN.
double gamma_p(double a, double x);

/// Regularized upper incomplete gamma function Q(a, x) = 1 - P(a, x), computed directly (not as
/// 1 - P) so that small upper tails keep their relative accuracy.
double gamma_q(double a, double x);

/// Chi-square cumulative distribution function with `dof` > 0 (real) degrees of freedom:
/// F(x; dof) = P(dof/2, x/2).
double chi2_cdf(double x, double dof);

/// Chi-square quantile: the x >= 0 with chi2_cdf(x, dof) = p, for 0 < p < 1 and dof > 0 (real).
/// Found by a bracketed Newton iteration on the logarithm of the smaller tail as a function of
/// ln x (every step that would leave the bracket is replaced by a bisection in log x), so that
/// it converges for any dof, including dof < 1 where the quantiles of small p are tiny.
/// Relative accuracy of the tail probability about 1e-13 (1e-14 * dof for very large dof).
/// Throws std::invalid_argument for p outside (0, 1) or dof <= 0.
double chi2_quantile(double p, double dof);

/// Regularized incomplete beta function I_x(a, b) for a, b > 0 and 0 <= x <= 1: the continued
/// fraction of DLMF 8.17.22 in modified Lentz form where it converges fast,
/// x < (a + 1) / (a + b + 2), and 1 - I_{1-x}(b, a) otherwise (DLMF 8.17.4); relative accuracy
/// about 1e-14 in the tail it evaluates directly. Throws std::invalid_argument for bad arguments.
double beta_inc(double a, double b, double x);

/// Two-sided tail P(|T| > t) of Student's t with nu > 0 degrees of freedom:
/// I_{nu / (nu + t^2)}(nu / 2, 1 / 2) (DLMF 8.17.1 with the t density), small tails to full
/// relative accuracy.
double student_t_two_sided(double t, double nu);

/// Digamma psi(x) = d ln Gamma(x) / dx for x > 0. With nu degrees of freedom,
/// E ln(chi2_nu / nu) = psi(nu/2) - ln(nu/2) (Bartlett & Kendall 1946, JRSS Suppl. 8). Absolute
/// accuracy about 1e-12.
double digamma(double x);

/// Trigamma psi'(x) for x > 0: var ln(chi2_nu / nu) = psi'(nu/2) (same source). Absolute
/// accuracy about 1e-12.
double trigamma(double x);

}  // namespace allanlot::kernels
