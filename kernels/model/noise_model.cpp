// The noise model's generic parts (noise_model.hpp).
#include "kernels/model/noise_model.hpp"

namespace allanlot::kernels {

void assign_effects(NoiseModel& to, const NoiseModel& from) {
  std::apply([&](auto... list) { ((to.*list = from.*list), ...); }, kEffectLists);
  to.lowpass = from.lowpass;
}

std::string effect_type_list() {
  std::string out;
  NoiseModel none;
  for_each_effect_list(none, [&](auto& list) {
    using E = typename std::decay_t<decltype(list)>::value_type;
    out += std::string(EffectTraits<E>::name) + ", ";
  });
  return out.substr(0, out.size() - 2) + " or " + std::string(EffectTraits<Lowpass>::name);
}

}  // namespace allanlot::kernels
