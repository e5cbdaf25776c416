// The markov effect's process (markov.hpp).
#include "kernels/simulate/markov.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace allanlot::kernels {

std::optional<CarriedStep> carried_step(const GaussMarkov& gm, double h) {
  if (!(gm.sigma > 0)) return std::nullopt;
  // OU: dm = -m/tau_c dt + sqrt(2 sigma^2 / tau_c) dW. Over one step h, given m_0, the pair
  // (m_h, I = integral_0^h m dt) is Gaussian with
  //   E m_h = phi m_0,                 Var m_h = sigma^2 (1 - phi^2),
  //   E I = tau_c (1 - phi) m_0,       Var I = sigma^2 tau_c^2 u(h / tau_c),
  //   Cov(I, m_h) = sigma^2 tau_c (1 - phi)^2,
  // (integrate the Ito representation m_t = phi_t m_0 + int e^{-(t-s)/tau_c} dW), drawn here by
  // the Cholesky factor of that 2x2 covariance.
  const double a = h / gm.tau_c_s;
  CarriedStep s;
  s.sigma = gm.sigma;
  s.phi = std::exp(-a);
  const double one_m_phi = -std::expm1(-a);
  s.s_m = gm.sigma * std::sqrt(-std::expm1(-2 * a));
  s.mean_i = gm.tau_c_s * one_m_phi;
  const double var_i = gm.sigma * gm.sigma * gm.tau_c_s * gm.tau_c_s * markov_u(a);
  const double cov = gm.sigma * gm.sigma * gm.tau_c_s * one_m_phi * one_m_phi;
  s.c = cov / s.s_m;
  s.d = std::sqrt(std::max(0.0, var_i - s.c * s.c));
  s.inv_h = 1.0 / h;
  return s;
}

double effect_avar(const GaussMarkov& g, double, double tau) {
  return markov_avar(g, tau);
}

double filter_change_avar(const GaussMarkov& g, const FilterAt& at) {
  return lowpass_markov_avar(g.sigma, g.tau_c_s, at.rate_hz, at.m, at.rho()) -
         markov_avar(g, at.tau);
}

void add_effect_psd(const GaussMarkov& g, double, std::span<const double> f_hz,
                    std::vector<double>& out) {
  for (std::size_t i = 0; i < f_hz.size(); ++i)
    out[i] += markov_psd_one_sided(g, 2 * std::numbers::pi * f_hz[i]);
}

}  // namespace allanlot::kernels
