// Simulate's generic path over the registered effects (kernels/simulate/effect_process.hpp):
// every effect is synthesized from its own stream, first_stream + its position in its list, and
// every effect's share reaches model_avar_sampled and model_psd_one_sided. Each check compares
// the generic path against a direct sum written out here, so a registered effect that the
// generic code skipped, drew from another stream or counted twice fails it.
#include "kernels/simulate/effects.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace kernels = allanlot::kernels;
using kernels::ChannelSpec;

namespace {

constexpr std::uint64_t kSeed = 20261129;
constexpr std::uint64_t kStream = 5;
// Two whole generation blocks (2^14 samples) and a partial one: the carries cross blocks.
constexpr std::size_t kN = 2 * 16384 + 77;

// Every effect outside eq. (3), two or more of each, a wandering resonance among them.
ChannelSpec all_effects() {
  ChannelSpec s;
  s.rate_hz = 100;
  s.sinusoids = {{0.01, 1.3, 0.2}, {0.02, 7.7, -1.0}};
  s.markovs = {{0.01, 0.5}, {0.0, 1.0}, {0.02, 5.0}};
  s.resonances = {{0.03, 17.0, 40.0}, {0.02, 21.0, 60.0, 0.5, 3.0}};
  s.steps = {{0.05, 100.0}, {-0.02, 234.567}};
  return s;
}

// The spec with every effect but list `list`'s effect `at` set to zero in place, so that each
// keeps its position (and its stream).
ChannelSpec only(const ChannelSpec& all, int list, std::size_t at) {
  ChannelSpec s = all;
  for (std::size_t i = 0; i < s.sinusoids.size(); ++i)
    if (list != 0 || i != at) s.sinusoids[i].amplitude = 0;
  for (std::size_t i = 0; i < s.markovs.size(); ++i)
    if (list != 1 || i != at) s.markovs[i].sigma = 0;
  for (std::size_t i = 0; i < s.resonances.size(); ++i)
    if (list != 2 || i != at) s.resonances[i].sigma = 0;
  for (std::size_t i = 0; i < s.steps.size(); ++i)
    if (list != 3 || i != at) s.steps[i].size = 0;
  return s;
}

std::vector<double> simulate(const ChannelSpec& s, int threads = 2) {
  std::vector<double> y(kN);
  kernels::simulate_channel(s, kSeed, kStream, y, threads);
  return y;
}

// Markov effect g drawn directly, one sample after another: the stationary start from pair 0 of
// stream `component`, sample k from pair k + 1 (carried_step's law), no blocks.
std::vector<double> markov_direct(const kernels::GaussMarkov& g, double rate_hz,
                                  std::uint32_t component) {
  const auto st = *kernels::carried_step(g, 1.0 / rate_hz);
  std::vector<double> y(kN);
  double m = g.sigma * kernels::rng::normal_pair(kSeed, kStream, component, 0).first;
  for (std::size_t k = 0; k < kN; ++k) {
    const auto [z1, z2] = kernels::rng::normal_pair(kSeed, kStream, component, k + 1);
    y[k] = (st.mean_i * m + st.c * z1 + st.d * z2) * st.inv_h;
    m = st.phi * m + st.s_m * z1;
  }
  return y;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

TEST(SimulateEffects, EachEffectFromItsOwnStreamAtItsPosition) {
  const ChannelSpec all = all_effects();
  using P = kernels::EffectProcess<kernels::GaussMarkov>;
  using R = kernels::EffectProcess<kernels::Resonance>;
  // Markov effect 2 from stream first_stream + 2, the block carries against the direct recursion
  // (their rounding differs: 1e-12 of sigma is a thousand times the doubles' own).
  EXPECT_LT(max_abs_diff(simulate(only(all, 1, 2)),
                         markov_direct(all.markovs[2], 100, P::first_stream + 2)),
            1e-12 * all.markovs[2].sigma);
  // Resonance 1 (the wandering one) from stream first_stream + 1: the same recursion, bit for bit.
  std::vector<double> direct(kN);
  kernels::add_resonance(all.resonances[1], all.rate_hz, kSeed, kStream, R::first_stream + 1,
                         direct);
  EXPECT_EQ(max_abs_diff(simulate(only(all, 2, 1)), direct), 0.0);
  // The deterministic ones: a sinusoid's interval mean and a step's share of each sample.
  std::vector<double> line(kN), jump(kN);
  kernels::add_effect_block(all.sinusoids[1], all.rate_hz, 0, line);
  kernels::add_steps(jump, std::span(&all.steps[0], 1), all.rate_hz);
  EXPECT_EQ(max_abs_diff(simulate(only(all, 0, 1)), line), 0.0);
  EXPECT_EQ(max_abs_diff(simulate(only(all, 3, 0)), jump), 0.0);
}

TEST(SimulateEffects, TheChannelIsTheSumOfItsEffects) {
  // Each effect draws its own stream, so the channel holding them all is the sum of the
  // channels holding one each (to rounding: the sums are ordered differently), at any thread
  // count.
  const ChannelSpec all = all_effects();
  std::vector<double> sum(kN, 0.0);
  const std::size_t sizes[] = {all.sinusoids.size(), all.markovs.size(), all.resonances.size(),
                               all.steps.size()};
  for (int list = 0; list < 4; ++list)
    for (std::size_t i = 0; i < sizes[list]; ++i) {
      const auto y = simulate(only(all, list, i), 1);
      for (std::size_t k = 0; k < kN; ++k)
        sum[k] += y[k];
    }
  EXPECT_LT(max_abs_diff(simulate(all), sum), 1e-14);
}

TEST(SimulateEffects, TheoryIsTheSumOfEachEffectsShare) {
  // model_avar_sampled (a finite record, the steps' share; under each form of the filter) and
  // the PSD of the channel are the sums of each effect's alone: every registered effect's share
  // reached the generic sums once.
  ChannelSpec all = all_effects();
  const std::size_t sizes[] = {all.sinusoids.size(), all.markovs.size(), all.resonances.size(),
                               all.steps.size()};
  for (const kernels::Lowpass lp :
       {kernels::Lowpass{}, kernels::Lowpass{15.0, 0}, kernels::Lowpass{0, 3.4}}) {
    all.lowpass = lp;
    for (const std::int64_t m : {1, 7, 100}) {
      double sum = 0;
      for (int list = 0; list < 4; ++list)
        for (std::size_t i = 0; i < sizes[list]; ++i)
          sum += kernels::model_avar_sampled(only(all, list, i), m, kN);
      const double total = kernels::model_avar_sampled(all, m, kN);
      EXPECT_NEAR(total / sum, 1.0, 1e-12) << "m " << m << " cutoff " << lp.cutoff_hz;
    }
  }
  const std::vector<double> f = {0.01, 1.3, 17.0, 21.5, 49.0};
  std::vector<double> sum(f.size(), 0.0);
  for (int list = 0; list < 4; ++list)
    for (std::size_t i = 0; i < sizes[list]; ++i) {
      const auto p = kernels::model_psd_one_sided(only(all, list, i), f);
      for (std::size_t j = 0; j < f.size(); ++j)
        sum[j] += p[j];
    }
  const auto total = kernels::model_psd_one_sided(all, f);
  for (std::size_t j = 0; j < f.size(); ++j)
    EXPECT_NEAR(total[j] / sum[j], 1.0, 1e-12) << f[j];
}

TEST(SimulateEffects, LowpassRulesOneOwnerSensibleMessages) {
  // validate_lowpass (simulate's and analyze's) applies the filter's traits: the model file's
  // reasons, naming the key.
  const auto message = [](const kernels::Lowpass& lp) -> std::string {
    try {
      kernels::validate_lowpass(lp, 100.0);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message({}), "");
  EXPECT_EQ(message({10.0, 0}), "");
  EXPECT_EQ(message({0, 2.5}), "");
  EXPECT_EQ(message({60.0, 0}),
            "lowpass.cutoff_hz: must be below the Nyquist frequency 50 Hz, got 60");
  EXPECT_EQ(message({-1.0, 0}), "lowpass.cutoff_hz: must be > 0, got -1");
  EXPECT_EQ(message({0, 0.5}), "lowpass.taps: must be in (1, 100000], got 0.5");
  EXPECT_EQ(message({0, std::nan("")}), "lowpass.taps: must be finite, got nan");
  EXPECT_EQ(message({10.0, 3.0}), "lowpass: has exactly one of cutoff_hz and taps, got both");
  // simulate names itself before the same reason.
  ChannelSpec s;
  s.rate_hz = 100;
  s.lowpass.cutoff_hz = 60;
  std::vector<double> y(8);
  try {
    kernels::simulate_channel(s, 1, 0, y);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "simulate: lowpass.cutoff_hz: must be below the Nyquist frequency 50 Hz, got 60");
  }
}
