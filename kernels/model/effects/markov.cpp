// The markov effect's Allan variance and PSD (markov.hpp).
#include "kernels/model/effects/markov.hpp"

#include <cmath>

namespace allanlot::kernels {

double markov_u(double a) {
  if (a < 0.5) {
    double sum = 0;
    double term = a * a * a / 6.0;  // a^k / k! at k = 3
    for (int k = 3; k <= 25; ++k) {
      const double c = (k % 2 == 0 ? 1.0 : -1.0) * (4.0 - std::ldexp(1.0, k));
      sum += c * term;
      term *= a / (k + 1);
    }
    return sum;
  }
  const double e = std::exp(-a);
  return 2 * a - 3 + 4 * e - e * e;
}

double markov_avar(const GaussMarkov& g, double tau) {
  return g.sigma * g.sigma * g.tau_c_s * g.tau_c_s * markov_u(tau / g.tau_c_s) / (tau * tau);
}

double markov_psd_one_sided(const GaussMarkov& g, double w) {
  const double wt = w * g.tau_c_s;
  return 4 * g.sigma * g.sigma * g.tau_c_s / (1 + wt * wt);
}

}  // namespace allanlot::kernels
