// Whether a lot of diagnosed channels is within noise as a whole (lot_noise.hpp).
#include "kernels/diagnose/lot_noise.hpp"

#include "kernels/common/quantile.hpp"
#include "kernels/diagnose/diagnose.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

namespace allanlot::kernels {

double beyond_p95_probability(int replicas) {
  if (replicas < 1) return std::numeric_limits<double>::quiet_NaN();
  const double r = replicas;
  return (r - exceedance_position(static_cast<std::size_t>(replicas), kGapNoiseQuantile)) /
         (r + 1.0);
}

double at_least_probability(std::span<const double> p, int k) {
  for (const double x : p)
    if (!(x >= 0.0 && x <= 1.0))
      throw std::invalid_argument("at_least_probability: a probability outside [0, 1]");
  if (k <= 0) return 1.0;
  if (static_cast<std::size_t>(k) > p.size()) return 0.0;
  // dist[j]: P(j successes so far), trial by trial; its tail from k is the answer.
  std::vector<double> dist(p.size() + 1, 0.0);
  dist[0] = 1.0;
  for (std::size_t t = 0; t < p.size(); ++t) {
    for (std::size_t j = t + 1; j > 0; --j)
      dist[j] = dist[j] * (1.0 - p[t]) + dist[j - 1] * p[t];
    dist[0] *= 1.0 - p[t];
  }
  double tail = 0.0;
  for (std::size_t j = static_cast<std::size_t>(k); j < dist.size(); ++j)
    tail += dist[j];
  return std::min(tail, 1.0);
}

}  // namespace allanlot::kernels
