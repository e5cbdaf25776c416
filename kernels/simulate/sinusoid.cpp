// The sinusoid effect's process (sinusoid.hpp).
#include "kernels/simulate/sinusoid.hpp"

#include <cmath>
#include <numbers>

namespace allanlot::kernels {

using std::numbers::pi;

void add_effect_block(const Sinusoid& s, double rate_hz, std::size_t first, std::span<double> y) {
  const double h = 1.0 / rate_hz;
  const double x = pi * s.frequency_hz * h;
  const double amp_avg = s.amplitude * std::sin(x) / x;
  const double cycles_per_sample = s.frequency_hz * h;
  // The phase reduced to whole cycles before sin(), so that a long record keeps its digits.
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double cyc = cycles_per_sample * (static_cast<double>(first + i) + 0.5);
    y[i] += amp_avg * std::sin(2 * pi * (cyc - std::floor(cyc)) + s.phase_rad);
  }
}

double effect_avar(const Sinusoid& s, double, double tau) {
  return sinusoid_avar(s, tau);
}

double filter_change_avar(const Sinusoid& s, const FilterAt& at) {
  return sinusoid_avar(s, at.tau) * (lowpass_gain2(at.lowpass, at.rate_hz, s.frequency_hz) - 1.0);
}

void add_effect_psd(const Sinusoid&, double, std::span<const double>, std::vector<double>&) {}

}  // namespace allanlot::kernels
