// The step effect: a bias jump. Its name and model-file keys; its samples and its Allan variance
// over a record (which depends on the record's length) are its process's, kernels/simulate/step.hpp
// (add_steps, step_avar_sampled and plus_steps_avar).
#pragma once

#include "kernels/model/effects/effect.hpp"

#include <array>
#include <optional>

namespace allanlot::kernels {

/// A bias jump: the rate error changes by `size` at `time_s` after the first sample's start and
/// stays (e.g. a turn-on transient ending, a mechanical shock, a temperature-driven bias shift).
/// The sample that straddles time_s takes the fraction of it that lies after the jump.
struct Step {
  double size = 0;    // [u], either sign
  double time_s = 0;  // > 0; a step at or after the record's end changes nothing
  friend bool operator==(const Step&, const Step&) = default;
};

template <>
struct EffectTraits<Step> {
  static constexpr std::string_view name = "step";
  static constexpr std::array<EffectKey<Step>, 2> keys = {{
      {"size", &Step::size, KeyRule::Finite, Presence::Required},
      {"time_s", &Step::time_s, KeyRule::Positive, Presence::Required},
  }};
  static constexpr std::size_t max_count = 0;
  // Its level is signed (the jump's direction); its Allan variance scales with size^2.
  static constexpr double Step::*level = &Step::size;
  static constexpr double Step::*shape = &Step::time_s;
  // Size and time come from the jump in the record (diagnose's time-domain witness).
  static constexpr int curve_parameters = 0;
  static std::optional<KeyProblem> check(const Step&, double, NumberText) { return std::nullopt; }
};

}  // namespace allanlot::kernels
