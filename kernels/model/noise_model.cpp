// The noise model's generic parts (noise_model.hpp).
#include "kernels/model/noise_model.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace allanlot::kernels {

void assign_effects(NoiseModel& to, const NoiseModel& from) {
  std::apply([&](auto... list) { ((to.*list = from.*list), ...); }, kEffectLists);
  to.lowpass = from.lowpass;
}

namespace {

// The shortest text that reads back as v (std::to_chars), for a message.
std::string shortest(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

// The problem with one key's value on its own, if any.
std::optional<std::string> key_problem(double v, KeyRule rule) {
  if (!std::isfinite(v)) return "must be finite, got " + shortest(v);
  if (rule == KeyRule::NonNegative && v < 0) return "must be >= 0, got " + shortest(v);
  if (rule == KeyRule::Positive && v <= 0) return "must be > 0, got " + shortest(v);
  return std::nullopt;
}

template <class E>
void validate_list(const std::vector<E>& list, double rate_hz, const std::string& what) {
  using Traits = EffectTraits<E>;
  const std::string name(Traits::name);
  if (Traits::max_count > 0 && list.size() > Traits::max_count)
    throw std::invalid_argument(what + ": at most " + std::to_string(Traits::max_count) + " " +
                                name + " effects, got " + std::to_string(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string at = what + ": " + name + "[" + std::to_string(i) + "]";
    for (const auto& k : Traits::keys) {
      if (k.presence == Presence::When && !k.needed(list[i])) continue;
      if (const auto reason = key_problem(list[i].*k.field, k.rule))
        throw std::invalid_argument(at + "." + std::string(k.name) + ": " + *reason);
    }
    if (const auto problem = Traits::check(list[i], rate_hz, shortest))
      throw std::invalid_argument(at + (problem->key.empty() ? "" : "." + problem->key) + ": " +
                                  problem->reason);
  }
}

}  // namespace

void validate_effects(const NoiseModel& m, const std::string& what) {
  for_each_effect_list(m, [&](const auto& list) { validate_list(list, m.rate_hz, what); });
}

void validate_lowpass(const Lowpass& lp, double rate_hz) {
  using Traits = EffectTraits<Lowpass>;
  const std::string name(Traits::name);
  if (lp == Lowpass{}) return;
  for (const auto& k : Traits::keys) {
    const double v = lp.*k.field;
    if (v == 0) continue;  // left out: Presence::OptionalNonzero
    if (const auto reason = key_problem(v, k.rule))
      throw std::invalid_argument(name + "." + std::string(k.name) + ": " + *reason);
  }
  if (lp.cutoff_hz != 0 && lp.taps != 0)
    throw std::invalid_argument(name + ": has exactly one of " + std::string(Traits::keys[0].name) +
                                " and " + std::string(Traits::keys[1].name) + ", got both");
  if (const auto problem = Traits::check(lp, rate_hz, shortest))
    throw std::invalid_argument(name + "." + problem->key + ": " + problem->reason);
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
