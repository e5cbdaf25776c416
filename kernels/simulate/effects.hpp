// Every registered effect's process (kernels/simulate/effect_process.hpp), one include each, and
// the check that their random streams stay apart: a channel's effect i of a list draws from
// stream EffectProcess<E>::first_stream + i, which rng::bits keeps in the counter's byte beside
// the channel's own components (kernels/simulate/rng.hpp).
#pragma once

#include "kernels/model/noise_model.hpp"
#include "kernels/simulate/markov.hpp"
#include "kernels/simulate/resonance.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/simulate/sinusoid.hpp"
#include "kernels/simulate/step.hpp"

#include <array>
#include <cstdint>
#include <tuple>

namespace allanlot::kernels {

namespace detail {

// Whether the registered effects' stream ranges [first_stream, first_stream + streams) lie at
// or above rng::kFirstEffectStream, below 256, and apart; an effect that draws streams must hold
// a bounded list (max_count > 0), one stream per effect.
consteval bool effect_streams_apart() {
  struct Range {
    std::uint32_t first, count;
    std::size_t max_count;
  };
  std::array<Range, std::tuple_size_v<decltype(kEffectLists)>> r{};
  std::size_t k = 0;
  std::apply(
      [&](auto... list) {
        ((r[k++] = Range{EffectProcess<EffectOf<decltype(NoiseModel{}.*list)>>::first_stream,
                         EffectProcess<EffectOf<decltype(NoiseModel{}.*list)>>::streams,
                         EffectTraits<EffectOf<decltype(NoiseModel{}.*list)>>::max_count}),
         ...);
      },
      kEffectLists);
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (r[i].count == 0) continue;
    if (r[i].count != r[i].max_count || r[i].first < rng::kFirstEffectStream ||
        r[i].first + r[i].count > 256)
      return false;
    for (std::size_t j = 0; j < i; ++j)
      if (r[j].count > 0 && r[i].first < r[j].first + r[j].count &&
          r[j].first < r[i].first + r[i].count)
        return false;
  }
  return true;
}

}  // namespace detail

static_assert(detail::effect_streams_apart(),
              "each registered effect's random streams (EffectProcess<E>::first_stream, one per "
              "effect up to EffectTraits<E>::max_count) lie in [rng::kFirstEffectStream, 256) and "
              "apart from the other effects'");

}  // namespace allanlot::kernels
