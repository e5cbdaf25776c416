// The resonance effect's checks (resonance.hpp).
#include "kernels/model/effects/resonance.hpp"

#include <algorithm>

namespace allanlot::kernels {

double resonance_max_spread(double frequency_hz, double rate_hz) {
  return std::min(frequency_hz, rate_hz / 2 - frequency_hz) / 5.0;
}

std::optional<KeyProblem> EffectTraits<Resonance>::check(const Resonance& r, double rate_hz,
                                                         NumberText text) {
  if (r.frequency_hz >= rate_hz / 2)
    return KeyProblem{"frequency_hz", "must be below the Nyquist frequency " + text(rate_hz / 2) +
                                          " Hz, got " + text(r.frequency_hz)};
  if (!(r.q >= kResonanceMinQ && r.q <= kResonanceMaxQ))
    return KeyProblem{"q", "must be in [" + text(kResonanceMinQ) + ", " + text(kResonanceMaxQ) +
                               "], got " + text(r.q)};
  const double top = resonance_max_spread(r.frequency_hz, rate_hz);
  if (r.spread_hz > top)
    return KeyProblem{"spread_hz",
                      "must be at most " + text(top) +
                          " Hz (a fifth of frequency_hz's distance to 0 or to the Nyquist "
                          "frequency), got " +
                          text(r.spread_hz)};
  return std::nullopt;
}

}  // namespace allanlot::kernels
