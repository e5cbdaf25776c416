#include "kernels/plan/sequential.hpp"

#include "kernels/uncertainty/chi2.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace allanlot::kernels {

double spent_alpha(double alpha, double t, double t_max) {
  return alpha * std::clamp(t / t_max, 0.0, 1.0);
}

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("normal_quantile: p must be in (0, 1)");
  // Z^2 is chi-square(1): |z| = sqrt(chi2_quantile(|2p - 1|, 1)), signed by p - 1/2.
  const double z = std::sqrt(chi2_quantile(std::abs(2.0 * p - 1.0), 1.0));
  return p < 0.5 ? -z : z;
}

double look_quantile(double alpha, double t_prev, double t, double t_max) {
  if (!(alpha > 0.0 && alpha < 1.0) || !(t_prev >= 0.0) || !(t > t_prev) || !(t_max > 0.0))
    throw std::invalid_argument("look_quantile: need 0 < alpha < 1, 0 <= t_prev < t, t_max > 0");
  const double a = spent_alpha(alpha, t, t_max) - spent_alpha(alpha, t_prev, t_max);
  if (!(a > 0.0)) return std::numeric_limits<double>::infinity();
  return normal_quantile(1.0 - a);
}

}  // namespace allanlot::kernels
