// The sinusoid effect's checks and Allan variance (sinusoid.hpp).
#include "kernels/model/effects/sinusoid.hpp"

#include <cmath>
#include <numbers>

namespace allanlot::kernels {

std::optional<KeyProblem> EffectTraits<Sinusoid>::check(const Sinusoid& s, double rate_hz,
                                                        NumberText text) {
  if (s.frequency_hz > rate_hz / 2)
    return KeyProblem{"frequency_hz", "must not exceed the Nyquist frequency " + text(rate_hz / 2) +
                                          " Hz, got " + text(s.frequency_hz)};
  return std::nullopt;
}

double sinusoid_avar(const Sinusoid& s, double tau) {
  const double x = std::numbers::pi * s.frequency_hz * tau;
  const double sx = std::sin(x);
  return s.amplitude * s.amplitude * sx * sx * sx * sx / (x * x);
}

}  // namespace allanlot::kernels
