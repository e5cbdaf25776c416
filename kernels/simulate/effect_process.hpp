// What simulate needs of each registered effect (kernels/model/noise_model.hpp kEffectLists), so
// that its synthesis and theory iterate the registered lists instead of naming the effects. Each
// effect's own file kernels/simulate/<name>.hpp specialises EffectProcess<E> (how its samples are
// made, which random streams it draws) and overloads, for E,
//
//   Synthesis::Block    add_effect_block(const E&, rate_hz, first, y)   a pure function of the
//                       sample's index, added block by block in parallel
//   Synthesis::Carried  carried_step(const E&, h) -> std::optional<CarriedStep>   an
//                       Ornstein-Uhlenbeck state carried across blocks (the random walk's engine)
//   Synthesis::Record   add_effect_record(const E&, rate_hz, seed, stream, component, y)
//                       sequential over the whole record
//   effect_avar(const E&, rate_hz, tau)              its share of model_avar (unfiltered)
//   filter_change_avar(const E&, const FilterAt&)    what the filter adds to that share
//   add_effect_psd(const E&, rate_hz, f_hz, out)     its one-sided PSD, added to out
//   plus_record_avar(v, span<const E>, ...)          optional: a share that depends on the
//                                                    record's length (the default adds none)
//
// A registered effect without its overloads does not compile; kernels/simulate/effects.hpp
// includes every effect's file and checks that their streams stay apart.
#pragma once

#include "kernels/model/effects/effect.hpp"
#include "kernels/simulate/lowpass.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

namespace allanlot::kernels {

/// How an effect's samples are made, which sets when simulate adds them: Block effects inside
/// the block loop (after the eq. (3) terms), then Carried ones' local recursions; Record effects
/// after the carries and flicker PM, before the filter. Each stage takes the registered lists
/// in kEffectLists order, so each sample's sum has a fixed order (and fixed bits).
enum class Synthesis { Block, Carried, Record };

/// Specialised by each effect's simulate file: `synthesis`, and the random streams it draws,
/// effect i of a channel's list from stream first_stream + i (streams = 0: none).
template <class E>
struct EffectProcess;

/// An effect that draws no random numbers: a pure function of the sample's index.
struct DeterministicProcess {
  static constexpr Synthesis synthesis = Synthesis::Block;
  static constexpr std::uint32_t first_stream = 0;
  static constexpr std::uint32_t streams = 0;
};

/// A random effect E synthesized as S: effect i of a channel's list draws stream First + i, one
/// stream for each of the EffectTraits<E>::max_count a channel may hold.
template <class E, Synthesis S, std::uint32_t First>
struct RandomProcess {
  static constexpr Synthesis synthesis = S;
  static constexpr std::uint32_t first_stream = First;
  static constexpr auto streams = static_cast<std::uint32_t>(EffectTraits<E>::max_count);
};

/// The effect type of a registered list (std::vector<E>).
template <class List>
using EffectOf = typename std::decay_t<List>::value_type;

/// Per-interval constants of a Carried effect: an Ornstein-Uhlenbeck state m over one sample
/// interval h, exactly discretized, and the sample as the state's mean over the interval
/// (kernels/simulate/markov.cpp derives them). The block engine (simulate.cpp) runs the
/// recursion from zero in each block and adds the true start state's share afterwards.
struct CarriedStep {
  double phi = 0;               // exp(-h / tau_c): AR(1) coefficient of the state
  double s_m = 0;               // sd of the state innovation, sigma sqrt(1 - phi^2)
  double mean_i = 0;            // E[integral | start state] / start state = tau_c (1 - phi)
  double c = 0;                 // integral's loading on the state innovation's normal
  double d = 0;                 // integral's own normal's loading
  double sigma = 0;             // stationary sd (initial state)
  double inv_h = 0;             // 1 / h: the sample is the interval mean
  std::uint32_t component = 0;  // its random stream (EffectProcess::first_stream + i)
};

/// Where model_avar_sampled asks what the filter does to an effect: the filter, the rate, the
/// averaging factor m and tau = m / rate_hz, and the filter's autocorrelation, computed on first
/// use so that only effects that need it pay for it.
class FilterAt {
public:
  FilterAt(const Lowpass& lp, double rate, std::int64_t m_at)
      : lowpass(lp), rate_hz(rate), m(m_at), tau(static_cast<double>(m_at) / rate) {}
  const Lowpass& lowpass;
  double rate_hz;
  std::int64_t m;
  double tau;
  const std::vector<double>& rho() const {
    if (!rho_) rho_ = lowpass_autocorrelation(lowpass, rate_hz);
    return *rho_;
  }

private:
  mutable std::optional<std::vector<double>> rho_;
};

/// A stationary effect's share of an Allan variance does not depend on the record's length:
/// `avar` unchanged. An effect whose share does (a step) overloads it for its span.
template <class E>
double plus_record_avar(double avar, std::span<const E>, double, std::int64_t, std::int64_t) {
  return avar;
}

}  // namespace allanlot::kernels
