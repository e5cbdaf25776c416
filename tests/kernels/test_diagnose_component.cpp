// kernels/diagnose/component.hpp: a model component is one part of the noise model. Every part
// names its effect and back, keeps its level (a step its direction), and a model taken apart
// into components and put together again is the model it was.
#include "kernels/diagnose/internal.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace allanlot {
namespace {

using namespace kernels::diagnose_detail;
using kernels::Effect;

// One component of every alternative of Part, default parameters.
std::vector<Component> every_part() {
  std::vector<Component> out;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (out.push_back(component(std::variant_alternative_t<I, Part>{})), ...);
  }
  (std::make_index_sequence<std::variant_size_v<Part>>{});
  return out;
}

TEST(DiagnoseComponent, EveryPartIsTheEffectOfItsName) {
  for (const Component& c : every_part()) {
    const Effect e = effect_of(c);
    EXPECT_EQ(kernels::parse_effect(kernels::effect_name(e)), e) << kernels::effect_name(e);
    if (is<TermLevel>(c)) {
      EXPECT_EQ(kernels::effect_term(e), as<TermLevel>(c).term);
    }
  }
  for (const kernels::Term t : kernels::all_terms()) {
    const Effect e = effect_of(component(TermLevel{t}));
    EXPECT_EQ(kernels::effect_term(e), t) << kernels::effect_name(e);
  }
  EXPECT_EQ(kernels::effect_name(effect_of(component(kernels::Resonance{}))), "resonance");
  EXPECT_EQ(kernels::effect_name(effect_of(component(kernels::GaussMarkov{}))), "markov");
}

// A witness names the effects whose parameters the record gives (a line, a jump); the terms and
// the effects searched on the curve are fitted there.
TEST(DiagnoseComponent, TheWitnessedEffectsAreTheLineAndTheJump) {
  for (const kernels::Effect e : kAllEffects) {
    const bool witnessed = e == Effect::Sinusoid || e == Effect::Step;
    EXPECT_EQ(witnessed_effect(e), witnessed) << kernels::effect_name(e);
  }
}

TEST(DiagnoseComponent, ALevelIsSetWithoutItsSign) {
  Component step = component(kernels::Step{-0.3, 12.0});
  EXPECT_EQ(coef(step), 0.3);
  set_coef(step, 0.5);
  EXPECT_EQ(as<kernels::Step>(step).size, -0.5);
  Component line = component(kernels::Sinusoid{0.2, 3.0});
  set_coef(line, 0.7);
  EXPECT_EQ(as<kernels::Sinusoid>(line).amplitude, 0.7);
  EXPECT_EQ(as<kernels::Sinusoid>(line).frequency_hz, 3.0);
  Component filter = component(kernels::Lowpass{0.0, 2.5});
  EXPECT_EQ(coef(filter), 1.0);  // present in full: no level of its own
  set_coef(filter, 0.0);
  EXPECT_EQ(as<kernels::Lowpass>(filter).taps, 2.5);
  Component white = component(TermLevel{kernels::Term::N, 0.01});
  set_coef(white, 0.02);
  EXPECT_EQ(coef(white), 0.02);
}

TEST(DiagnoseComponent, AModelTakenApartIsTheModelAgain) {
  kernels::ChannelSpec m;
  m.rate_hz = 100.0;
  m.terms.N = 0.01;
  m.terms.K = 2e-4;
  m.offset = 1.0;
  m.quantum = 0.003;
  m.sinusoids = {{0.02, 0.7, 0.3}, {0.01, 2.0, 0.0}};
  m.markovs = {{0.004, 30.0}};
  m.resonances = {{0.05, 12.0, 20.0}, {0.03, 30.0, 10.0, 1.0, 50.0}};
  m.steps = {{-0.02, 1500.0}, {0.01, 2000.0}};
  m.lowpass.taps = 1.6;
  const std::vector<Component> comps = components_of(m);
  EXPECT_EQ(comps.size(), 2u + 2u + 1u + 2u + 2u + 1u);
  for (const Component& c : comps) {
    EXPECT_TRUE(c.given);
    EXPECT_EQ(c.pinned, is<kernels::Step>(c) || is<kernels::Lowpass>(c));
  }
  EXPECT_EQ(spec_of(comps, m), m);
  // The revision names and the labels count each effect's components apart.
  EXPECT_EQ(component_label(comps, 0), "K");
  EXPECT_EQ(component_label(comps, 3), "sinusoid[1]");
  EXPECT_EQ(component_label(comps, comps.size() - 1), "lowpass");
}

}  // namespace
}  // namespace allanlot
