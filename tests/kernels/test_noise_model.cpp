// The noise model's registration and its generic parts (kernels/model/noise_model.hpp): what
// the model file, simulate's checks and a diagnosed model's copy take from the registered
// effects' traits.
#include "kernels/model/noise_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace kernels = allanlot::kernels;

namespace {

// The message of validate_effects for m, empty when it passes.
std::string problem(const kernels::NoiseModel& m) {
  try {
    kernels::validate_effects(m, "test");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

kernels::NoiseModel valid_model() {
  kernels::NoiseModel m;
  m.rate_hz = 100;
  m.sinusoids.push_back({0.1, 50.0, 0.3});  // exactly Nyquist is allowed
  m.markovs.push_back({0.2, 3.0});
  m.resonances.push_back({0.3, 17.0, 40.0, 0.5, 20.0});
  m.steps.push_back({-0.4, 12.5});
  return m;
}

}  // namespace

TEST(NoiseModel, EveryRegisteredEffectHasItsOwnNameAndDistinctKeys) {
  std::set<std::string> names = {std::string(kernels::EffectTraits<kernels::Lowpass>::name)};
  kernels::NoiseModel m;
  int lists = 0;
  kernels::for_each_effect_list(m, [&](const auto& list) {
    using E = typename std::decay_t<decltype(list)>::value_type;
    using Traits = kernels::EffectTraits<E>;
    ++lists;
    EXPECT_TRUE(names.insert(std::string(Traits::name)).second) << Traits::name;
    std::set<std::string_view> keys = {"type"};
    for (const auto& k : Traits::keys) {
      EXPECT_TRUE(keys.insert(k.name).second) << Traits::name << "." << k.name;
      EXPECT_EQ(k.presence == kernels::Presence::When, k.needed != nullptr) << k.name;
    }
  });
  EXPECT_EQ(lists, 4);
  EXPECT_EQ(kernels::effect_type_list(), "sinusoid, markov, resonance, step or lowpass");
}

TEST(NoiseModel, ValidateEffectsNamesTheEffectTheKeyAndTheReason) {
  EXPECT_EQ(problem(valid_model()), "");
  auto m = valid_model();
  m.sinusoids[0].frequency_hz = 50.5;
  EXPECT_EQ(problem(m), "test: sinusoid[0].frequency_hz: must not exceed the Nyquist frequency "
                        "50 Hz, got 50.5");
  m = valid_model();
  m.markovs[0].tau_c_s = 0;
  EXPECT_EQ(problem(m), "test: markov[0].tau_c_s: must be > 0, got 0");
  m = valid_model();
  m.steps[0].size = std::nan("");
  EXPECT_EQ(problem(m).rfind("test: step[0].size: must be finite", 0), 0u) << problem(m);
  m = valid_model();
  m.resonances[0].wander_s = 0;  // required with a spread
  EXPECT_EQ(problem(m), "test: resonance[0].wander_s: must be > 0, got 0");
  m.resonances[0].spread_hz = 0;  // a stationary resonance: the wander is not read
  EXPECT_EQ(problem(m), "");
  m.resonances[0].q = 0.25;
  EXPECT_EQ(problem(m), "test: resonance[0].q: must be in [0.5, 1e+05], got 0.25");
  m = valid_model();
  m.markovs.assign(201, {0.1, 1.0});
  EXPECT_EQ(problem(m), "test: at most 200 markov effects, got 201");
}

TEST(NoiseModel, AssignEffectsCopiesTheEffectsAndTheFilterOnly) {
  const kernels::NoiseModel from = [] {
    auto m = valid_model();
    m.lowpass.taps = 2.5;
    m.terms.N = 7;
    m.offset = 9.8;
    return m;
  }();
  kernels::NoiseModel to;
  to.quantum = 0.01;
  kernels::assign_effects(to, from);
  EXPECT_EQ(to.sinusoids, from.sinusoids);
  EXPECT_EQ(to.markovs, from.markovs);
  EXPECT_EQ(to.resonances, from.resonances);
  EXPECT_EQ(to.steps, from.steps);
  EXPECT_EQ(to.lowpass, from.lowpass);
  EXPECT_EQ(to.terms.N, 0.0);
  EXPECT_EQ(to.offset, 0.0);
  EXPECT_EQ(to.quantum, 0.01);
}
