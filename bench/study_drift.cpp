// The drift sigma study (docs/validation/2026-11-28-drift.md; not a benchmark): simulated clocks
// of white FM plus random-walk FM (summed white noise) plus a known linear drift, the drift
// fitted by kernels::fit_drift, and, over SEEDS seeds, the spread of its sigma against the sigma
// the true noise levels give and the coverage of its 3-sigma interval.
//   study_drift [N] [WALK] [SEEDS]   (defaults 4096, 2e-13, 400; white FM 1e-11, tau0 1 s)
#include "kernels/drift/drift.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

using allanlot::kernels::DataType;
using allanlot::kernels::DriftModel;

namespace {

// The least-squares slope's sigma under the true noise levels.
double true_sigma(std::size_t n, double white, double walk) {
  const double tm = (static_cast<double>(n) - 1) / 2;
  double s2 = 0;
  for (std::size_t i = 0; i < n; ++i)
    s2 += (static_cast<double>(i) - tm) * (static_cast<double>(i) - tm);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i)
    v[i] = (static_cast<double>(i) - tm) / s2;
  return std::sqrt(allanlot::kernels::functional_variance(v, {}, {0, white * white, walk * walk}));
}

}  // namespace

int main(int argc, char** argv) {
  const auto n = static_cast<std::size_t>(argc > 1 ? std::atol(argv[1]) : 4096);
  const double walk = argc > 2 ? std::atof(argv[2]) : 2e-13;
  const int seeds = argc > 3 ? std::atoi(argv[3]) : 400;
  constexpr double white = 1e-11, drift = 3e-15;
  const double st = true_sigma(n, white, walk);
  std::vector<double> ratios;
  double z2 = 0;
  int beyond3 = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    std::mt19937_64 rng(static_cast<unsigned>(seed));
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> y(n);
    double rw = 0;
    for (std::size_t i = 0; i < n; ++i) {
      rw += walk * g(rng);
      y[i] = 1e-9 + drift * static_cast<double>(i) + white * g(rng) + rw;
    }
    const auto f = allanlot::kernels::fit_drift(y, DataType::Rate, 1.0, DriftModel::Linear);
    ratios.push_back(f.sigma[1] / st);
    const double z = (f.value[1] - drift) / f.sigma[1];
    z2 += z * z;
    beyond3 += std::abs(z) > 3;
  }
  std::sort(ratios.begin(), ratios.end());
  const auto q = [&](double p) {
    return ratios[static_cast<std::size_t>(p * static_cast<double>(ratios.size() - 1))];
  };
  std::printf("N %zu walk %g seeds %d: sigma/true min %.3f p0.5 %.3f p50 %.3f p99.5 %.3f max "
              "%.3f; rms z %.3f; |z| > 3 in %d\n",
              n, walk, seeds, ratios.front(), q(0.005), q(0.5), q(0.995), ratios.back(),
              std::sqrt(z2 / seeds), beyond3);
}
