// The lowpass effect's checks (lowpass.hpp).
#include "kernels/model/effects/lowpass.hpp"

#include <string>

namespace allanlot::kernels {

std::optional<KeyProblem> EffectTraits<Lowpass>::check(const Lowpass& lp, double rate_hz,
                                                       NumberText text) {
  if (lp.cutoff_hz >= rate_hz / 2)
    return KeyProblem{"cutoff_hz", "must be below the Nyquist frequency " + text(rate_hz / 2) +
                                       " Hz, got " + text(lp.cutoff_hz)};
  if (lp.cutoff_hz == 0 && !(lp.taps > 1 && lp.taps <= kLowpassMaxTaps))  // the moving average
    return KeyProblem{"taps", "must be in (1, " + std::to_string(kLowpassMaxTaps) + "], got " +
                                  text(lp.taps)};
  return std::nullopt;
}

}  // namespace allanlot::kernels
