// kernels/diagnose: hidden effects are named with their parameters, a complete model gets
// nothing, a wrong coefficient is reported as wrong rather than as a missing effect, and the
// result does not depend on the thread count. The rates over many seeds are in
// test_diagnose_study.cpp (disabled by default); here one or two seeds per case keep CTest fast.
#include "kernels/test_diagnose_support.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace allanlot {
namespace {

using kernels::Effect;
using test::find_param;

std::vector<Effect> sorted(std::vector<Effect> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// Bound on the gap of a model that explains the data: gap^2 = mean z^2 is about a chi-square
// with n_eff degrees of freedom over n_eff (Satterthwaite; see kernels/diagnose/diagnose.hpp), so
// its 99.9 % quantile bounds the gap for all but one seed in a thousand.
double gap_bound(const kernels::Diagnosis& d) {
  return std::sqrt(kernels::chi2_quantile(0.999, d.n_eff) / d.n_eff);
}

void check_scenario(const test::Scenario& s, std::uint64_t seed) {
  SCOPED_TRACE(s.name + ", seed " + std::to_string(seed));
  const kernels::Diagnosis d = test::run_scenario(s.truth, s.given, seed, 0, 2);
  EXPECT_EQ(sorted(d.effects_named), sorted(s.hidden));
  EXPECT_GT(d.before.gap, d.after.gap);
  EXPECT_LT(d.after.gap, gap_bound(d));
  EXPECT_FALSE(d.before.bands.empty());  // the disagreement is visible where it is
  if (!s.truth.sinusoids.empty()) {
    const auto* f = find_param(d, Effect::Sinusoid, "frequency_hz");
    ASSERT_NE(f, nullptr);
    EXPECT_NEAR(f->value, s.truth.sinusoids[0].frequency_hz,
                0.05 * s.truth.sinusoids[0].frequency_hz);
  }
  if (!s.truth.markovs.empty()) {
    const auto* t = find_param(d, Effect::Markov, "tau_c_s");
    ASSERT_NE(t, nullptr);
    // The issue's bar: 35 % (the seed study's worst of 20 is 28 %); the reported 1-sigma must
    // also cover the truth within 4 sigma.
    EXPECT_NEAR(t->value, s.truth.markovs[0].tau_c_s, 0.35 * s.truth.markovs[0].tau_c_s);
    EXPECT_NEAR(t->value, s.truth.markovs[0].tau_c_s, 4.0 * t->sigma);
  }
  if (!s.truth.resonances.empty()) {
    const auto* f = find_param(d, Effect::Resonance, "frequency_hz");
    ASSERT_NE(f, nullptr);
    EXPECT_NEAR(f->value, s.truth.resonances[0].frequency_hz,
                0.05 * s.truth.resonances[0].frequency_hz);
  }
  if (!s.truth.steps.empty()) {
    // The witness's time within its stated scale, the size within 3 sigma, the sign kept.
    const auto* t = find_param(d, Effect::Step, "time_s");
    const auto* z = find_param(d, Effect::Step, "size");
    ASSERT_NE(t, nullptr);
    ASSERT_NE(z, nullptr);
    EXPECT_LE(std::abs(t->value - s.truth.steps[0].time_s), t->sigma);
    EXPECT_NEAR(z->value, s.truth.steps[0].size, 3.0 * z->sigma);
  }
  // Named effects carry their parameters under the model file's keys (a step's size is signed).
  ASSERT_EQ(d.effect_parameters.size(), d.effects_named.size());
  for (const auto& ps : d.effect_parameters)
    for (const auto& p : ps)
      EXPECT_GT(p.name == "size" ? std::abs(p.value) : p.value, 0.0) << p.name;
}

TEST(Diagnose, EachHiddenEffectIsNamed) {
  for (const auto& s : test::hidden_scenarios())
    if (s.hidden.size() == 1) check_scenario(s, 1001);
}

TEST(Diagnose, TwoHiddenEffectsAreTwoNamedEffects) {
  for (const auto& s : test::hidden_scenarios())
    if (s.name == "markov+quantization" || s.name == "sinusoid+markov" ||
        s.name == "step+random_walk")
      check_scenario(s, 1001);
}

// The scenario `name` of test_diagnose_support.hpp at `level` (test::kLevels).
test::Scenario scenario_at(const std::string& name, const std::string& level) {
  for (const auto& l : test::kLevels)
    if (level == l.name)
      for (const auto& s : test::hidden_scenarios())
        if (s.name == name) return test::at_level(s, l);
  throw std::invalid_argument("no scenario " + name + "/" + level);
}

bool has_note(const kernels::Diagnosis& d, const std::string& text) {
  return std::any_of(d.notes.begin(), d.notes.end(),
                     [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

TEST(Diagnose, ARandomWalksTrendIsNotARamp) {
  // Seed 1003's random walk holds a trend whose tau^2 rise a ramp fits better at the longest
  // taus (the curve alone names it ramp, at the weak and medium levels); without the
  // record's line the walk's rise below the longest taus remains, and it is named.
  for (const char* level : {"weak", "medium"}) {
    SCOPED_TRACE(level);
    const test::Scenario s = scenario_at("random_walk", level);
    const auto d = test::run_scenario(s.truth, s.given, 1003, 0, 2);
    EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::RandomWalk});
    EXPECT_TRUE(has_note(d, "without its least-squares line")) << level;
  }
  // A true ramp keeps its name: nothing is left of it without the line.
  const test::Scenario r = scenario_at("ramp", "medium");
  for (const std::uint64_t seed : {1001u, 1003u}) {
    const auto d = test::run_scenario(r.truth, r.given, seed, 0, 2);
    EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::Ramp}) << seed;
  }
}

// Seed 1004's weak step (6.4 rms of the witness's differences) is seen by the change-point test
// at p = 0.004, short of its own level of 1e-3, and the curve alone scores a random walk (+36.6)
// about as high as the step (+37.3, its size charged as the walk's K): the curve alone would
// name random_walk. The jump decides between the two look-alikes, and the step is named.
TEST(Diagnose, AJumpShortOfTheWitnesssLevelTellsAStepFromAWalk) {
  const test::Scenario s = scenario_at("step", "weak");
  const auto d = test::run_scenario(s.truth, s.given, 1004, 0, 2);
  EXPECT_FALSE(d.step.found);
  EXPECT_GT(d.step.p_value, 1e-3);
  EXPECT_LT(d.step.p_value, 0.05);
  EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::Step});
  EXPECT_TRUE(has_note(d, "short of the change-point test's level"));
  ASSERT_EQ(d.model_after.steps.size(), 1u);
  EXPECT_NEAR(d.model_after.steps[0].time_s, 250.3, 1.0);
}

// A ramp of R = 1e-4 over a walk of K = `k` that `seed` does not name alone: the ramp is named,
// for the reason the round's note gives.
void expect_ramp_over_unnamed_walk(double k, std::uint64_t seed, const std::string& note) {
  SCOPED_TRACE(note);
  const kernels::ChannelSpec given = test::base_model();
  kernels::ChannelSpec walk = given;
  walk.terms.K = k;
  kernels::ChannelSpec truth = walk;
  truth.terms.R = 1e-4;
  const auto d = test::run_scenario(truth, given, seed, 0, 2);
  EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::Ramp});
  EXPECT_TRUE(has_note(d, note));
  EXPECT_TRUE(test::run_scenario(walk, given, seed, 0, 2).effects_named.empty());
}

TEST(Diagnose, ARampTheCurveTakesForAWalkIsNamedByItsSlope) {
  // The other way round: seed 1006's ramp (R = 1e-4) over a walk too small to be named alone
  // (K = 2.5e-4, a thirty-second of the weak level's variance) is fitted better by a random
  // walk on the curve (4 of seeds 1001-1030 are). Without the record's line the walk improves
  // the chi-square by less than its 95 % quantile under no walk, and the slope is far outside
  // the model's spread: the ramp is named, with a note (as a 20-sigma ramp injected into the
  // real imu3 x gyroscope is).
  expect_ramp_over_unnamed_walk(2.5e-4, 1006, "no longer shows the random walk");
  // In doubt the walk keeps its name: seed 1008's walk of K = 1e-3 holds a trend (slope z = 7
  // under the base model) and, without its line, still improves the chi-square by 6.8, which no
  // walk at all gives 1 time in 100. Named ramp when any criterion below the round's took it.
  kernels::ChannelSpec walk = test::base_model();
  walk.terms.K = 1e-3;
  const auto w = test::run_scenario(walk, test::base_model(), 1008, 0, 2);
  EXPECT_EQ(w.effects_named, std::vector<Effect>{Effect::RandomWalk});
}

TEST(Diagnose, ARampBeyondTheSpreadOfTheWalkBesideItIsNamed) {
  // Seed 1010's walk of K = 3e-4 is not named alone. With a ramp of R = 1e-4 on it (slope z 11.4
  // under the base model) the curve names a random walk, and without the record's line the walk
  // still improves the chi-square by 6.0, above 3.84: the rule above keeps a walk then. But beside
  // that walk's K the slope stands at z 3.2 (p 0.0015), beyond the round's level (0.005): a trend
  // the walk does not explain, and the ramp is named (random_walk before, as a ramp of 10 witness
  // sigma injected into the real imu4 gyro_x was).
  expect_ramp_over_unnamed_walk(3e-4, 1010, "beyond that walk's spread");
}

TEST(Diagnose, ARampTooSmallForTheCurveIsSeenInTheSlope) {
  // Over white FM the slope's spread is 12 N^2 / T^3 while a ramp's Allan variance R^2 tau^2 / 2
  // exceeds N^2 / tau by 6 z^2 (tau / T)^3 only, 0.1 z^2 at the longest tau (T / 4, two or three
  // edf): a ramp of 6 slope sigma is a few tens of percent there and within the estimate's
  // spread, but its witness stands at z = 6. With the witness switched off (a false alarm of
  // 1e-300) the curve alone misses it on these seeds.
  kernels::ChannelSpec given;
  given.rate_hz = test::kRateHz;
  given.terms.N = 0.01;
  kernels::ChannelSpec truth = given;
  truth.terms.R = 6.0 * std::sqrt(kernels::trend_slope_variance(given, test::kDurationS));
  kernels::DiagnoseOptions off;
  off.trend_false_alarm = 1e-300;
  for (const std::uint64_t seed : {1001u, 1002u}) {
    SCOPED_TRACE(seed);
    const auto d = test::run_scenario(truth, given, seed, 0, 2);
    ASSERT_EQ(d.effects_named, std::vector<Effect>{Effect::Ramp});
    const auto* r = find_param(d, Effect::Ramp, "R");
    ASSERT_NE(r, nullptr);
    EXPECT_NEAR(r->value, truth.terms.R, 4.0 * r->sigma);
    const auto& cands = d.iterations[0].candidates;
    EXPECT_TRUE(std::any_of(cands.begin(), cands.end(), [](const kernels::Candidate& c) {
      return c.effect == Effect::Ramp && c.note.find("slope") != std::string::npos;
    }));
    EXPECT_TRUE(test::run_scenario(truth, given, seed, 0, 2, off).effects_named.empty());
  }
  // A complete model's record has no trend to find (and the study's null case: 0 of 10).
  const auto none = test::run_scenario(given, given, 1001, 0, 2);
  EXPECT_TRUE(none.effects_named.empty());
}

TEST(Diagnose, AHumpMustShowItsTurnover) {
  // Seed 1001's strong random walk falls low at its longest taus, which a Gauss-Markov hump
  // fitted better by more than its extra parameter costs in a free choice; but its peak (about
  // 67 s) has less than an octave of taus beyond it (the last is 133 s), so its turnover is not
  // measured, and the random walk it contains as tau_c grows is named.
  const test::Scenario s = scenario_at("random_walk", "strong");
  const auto d = test::run_scenario(s.truth, s.given, 1001, 0, 2);
  EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::RandomWalk});
  EXPECT_TRUE(has_note(d, "is not within the taus measured"));
  // A hump that does turn over within the record is still named.
  const test::Scenario m = scenario_at("markov", "weak");
  EXPECT_EQ(test::run_scenario(m.truth, m.given, 1001, 0, 2).effects_named,
            std::vector<Effect>{Effect::Markov});
}

TEST(Diagnose, AWeakLineSeenByThePsdIsNamed) {
  // At the weak level the line's Allan bump alone is below the two-parameter penalty (named in
  // 2 of 10 records before), while the periodogram sees it at 1e-4 per record: its witness
  // decides, and the curve must only agree better with it.
  const test::Scenario s = scenario_at("sinusoid", "weak");
  for (const std::uint64_t seed : {1001u, 1002u}) {
    const auto d = test::run_scenario(s.truth, s.given, seed, 0, 2);
    EXPECT_EQ(d.effects_named, std::vector<Effect>{Effect::Sinusoid}) << seed;
  }
  // Beside a hump, the line's peak is below the whole record's Bonferroni threshold (19.5 for
  // 30000 bins at 1e-4); searched again where the Allan curve is above the model (fewer bins,
  // a lower threshold), it is found.
  const test::Scenario h = scenario_at("sinusoid+markov", "weak");
  const auto d = test::run_scenario(h.truth, h.given, 1001, 0, 2);
  EXPECT_EQ(sorted(d.effects_named), sorted({Effect::Sinusoid, Effect::Markov}));
  EXPECT_TRUE(d.line.found);
  EXPECT_LT(d.line.peak_ratio, std::log(30000.0 / 1e-4));
  EXPECT_LT(d.line.threshold, d.line.peak_ratio);
}

TEST(Diagnose, SensorFilterIsNamedAsALowpass) {
  // The base sensor behind a first-order filter at 15 Hz (100 Hz samples): N^2 / tau loses 24 %
  // at tau0 and 5 % at 4 tau0 (lowpass_white_fm_factor), a deficit of dozens of sigma at the
  // shortest taus of 60000 samples, as the real ADIS16405 recordings show.
  auto truth = test::base_model();
  truth.lowpass.cutoff_hz = 15.0;
  const auto d = test::run_scenario(truth, test::base_model(), 1001, 0, 2);
  ASSERT_EQ(d.effects_named, std::vector<Effect>{Effect::Lowpass});
  ASSERT_EQ(d.effect_parameters[0].size(), 1u);
  EXPECT_EQ(d.effect_parameters[0][0].name, "cutoff_hz");
  EXPECT_EQ(d.effect_parameters[0][0].bound, 0);
  // The grid's step is 9 % (8 per octave); the fit's scatter is well below it here.
  EXPECT_NEAR(d.effect_parameters[0][0].value, 15.0, 0.15 * 15.0);
  EXPECT_EQ(d.model_after.lowpass.cutoff_hz, d.effect_parameters[0][0].value);
  EXPECT_LT(d.after.gap, gap_bound(d));
}

TEST(Diagnose, SensorResonanceIsNamed) {
  // The ADIS16405 z gyroscopes' narrowband noise (docs/diagnose.md "Real sensors") scaled to the
  // base sensor behind its known filter: 20 Hz, q = 40, sigma 0.05, whose ripples at 1-4 samples
  // are 40-70 % of the filtered white noise's Allan variance there.
  auto given = test::base_model();
  given.lowpass.cutoff_hz = 28.0;
  auto truth = given;
  truth.resonances.push_back({0.05, 20.0, 40.0});
  const auto d = test::run_scenario(truth, given, 1001, 0, 2);
  ASSERT_EQ(d.effects_named, std::vector<Effect>{Effect::Resonance});
  ASSERT_EQ(d.effect_parameters[0].size(), 3u);
  const auto& f = d.effect_parameters[0][1];
  EXPECT_EQ(f.name, "frequency_hz");
  EXPECT_EQ(f.bound, 0);
  EXPECT_NEAR(f.value, 20.0, 0.02 * 20.0);
  EXPECT_NEAR(f.value, 20.0, 4.0 * f.sigma);
  EXPECT_NEAR(d.effect_parameters[0][0].value, 0.05, 0.2 * 0.05);
  EXPECT_EQ(d.model_after.resonances.size(), 1u);
  EXPECT_LT(d.after.gap, gap_bound(d));
}

// A narrower resonance (q = 100, half-width 0.1 Hz) wandering as the ADIS16405 z gyroscopes' does
// (its frequency's sd 0.8 Hz, correlation time 20 s): named wandering, with the spread and the
// wander's time measured on the periodogram and the frequency's track (at q = 40 the wander's
// likelihood ratio in 600 s, 12, stays below the 15.1 of 1e-4, and a stationary q = 15 is named).
// The record holds about T / (2 wander_s) = 15 independent frequencies, so the spread's relative sd
// is about 1 / sqrt(2 15) = 18 % beyond the fit's sigma: within 3 of both. The track's time errs
// short (find_narrowband.cpp): between a fifth of and twice the truth.
TEST(Diagnose, WanderingSensorResonanceIsNamedWithItsSpread) {
  auto given = test::base_model();
  given.lowpass.cutoff_hz = 28.0;
  auto truth = given;
  truth.resonances.push_back({0.05, 20.0, 100.0, 0.8, 20.0});
  const auto d = test::run_scenario(truth, given, 1001, 8, 2);
  ASSERT_EQ(d.effects_named, std::vector<Effect>{Effect::Resonance});
  ASSERT_EQ(d.effect_parameters[0].size(), 5u);
  const auto& spread = d.effect_parameters[0][3];
  EXPECT_EQ(spread.name, "spread_hz");
  EXPECT_NEAR(spread.value / 0.8, 1.0, 3.0 * std::hypot(spread.sigma / 0.8, 0.18));
  const auto& wander = d.effect_parameters[0][4];
  EXPECT_EQ(wander.name, "wander_s");
  EXPECT_GT(wander.value, 4.0);
  EXPECT_LT(wander.value, 40.0);
  ASSERT_EQ(d.model_after.resonances.size(), 1u);
  EXPECT_EQ(d.model_after.resonances[0].spread_hz, spread.value);
  EXPECT_EQ(d.model_after.resonances[0].wander_s, wander.value);
  EXPECT_LT(d.after.gap, gap_bound(d));
}

TEST(Diagnose, CompleteModelGetsNothing) {
  for (const std::uint64_t seed : {1001u, 1002u}) {
    SCOPED_TRACE(seed);
    const auto d = test::run_scenario(test::base_model(), test::base_model(), seed, 8, 2);
    EXPECT_TRUE(d.effects_named.empty());
    EXPECT_TRUE(d.iterations.empty());
    EXPECT_FALSE(d.coefficients_wrong);
    EXPECT_EQ(d.model_after.terms, d.model_before.terms);
    EXPECT_TRUE(d.after.bands.empty());
    EXPECT_LT(d.after.gap, gap_bound(d));
    EXPECT_EQ(d.mc_after.replicas, 8);
    EXPECT_EQ(d.mc_after.gaps.size(), 8u);
  }
}

// A complete model's record that ends beyond its replicas' p95 (the null study's seed 26: gap
// 1.34 against 1.14) fails the verdict's test by chance. The verdict's round then sees effects on
// the curve alone above its level (a hump: criterion +1.4 at 5 %), which named it in a first try
// (8 false alarms in 200 such records); with no witness beside the curve it names nothing, and
// with 4 replicas, whose p95 a complete model's record exceeds once in 5, it is not asked.
TEST(Diagnose, TheVerdictsRoundNamesOnlyWitnessedEffects) {
  const auto d = test::run_scenario(test::base_model(), test::base_model(), 1026, 20, 1);
  EXPECT_TRUE(d.effects_named.empty());
  EXPECT_FALSE(d.gap_within_noise);
  EXPECT_TRUE(has_note(d, "a round of the witnessed effects at the verdict's level"));
  EXPECT_TRUE(has_note(d, "named nothing"));
  const std::string& note = d.notes.back();
  const auto markov = note.find("markov ");
  ASSERT_NE(markov, std::string::npos) << note;
  EXPECT_GT(std::stod(note.substr(markov + 7)), 0.0) << note;
  EXPECT_NE(note.find("(no witness)", markov), std::string::npos) << note;
  const auto few = test::run_scenario(test::base_model(), test::base_model(), 1026, 4, 1);
  EXPECT_FALSE(has_note(few, "verdict's level"));
}

TEST(Diagnose, WrongCoefficientIsWrongNotIncomplete) {
  auto given = test::base_model();
  given.terms.N *= 1.3;
  const auto d = test::run_scenario(test::base_model(), given, 1001, 0, 2);
  EXPECT_TRUE(d.effects_named.empty());
  EXPECT_TRUE(d.coefficients_wrong);
  EXPECT_LT(d.after.gap, gap_bound(d));
  bool seen = false;
  for (const auto& r : d.revisions)
    if (r.name == "N") {
      seen = true;
      EXPECT_DOUBLE_EQ(r.given, given.terms.N);
      // The estimate is within 4 sigma of the truth and far from the given value.
      EXPECT_NEAR(r.estimated, test::base_model().terms.N, 4.0 * r.sigma);
      EXPECT_GT(std::abs(r.estimated - r.given), 10.0 * r.sigma);
    }
  EXPECT_TRUE(seen);
  EXPECT_NEAR(d.model_after.terms.N, test::base_model().terms.N, 0.01 * test::base_model().terms.N);
}

TEST(Diagnose, SameResultForAnyThreadCount) {
  auto truth = test::base_model();
  truth.terms.Q = 3e-4;
  const auto a = test::run_scenario(truth, test::base_model(), 5, 4, 1);
  const auto b = test::run_scenario(truth, test::base_model(), 5, 4, 2);
  EXPECT_EQ(a.effects_named, b.effects_named);
  EXPECT_EQ(a.after.avar_model, b.after.avar_model);
  EXPECT_EQ(a.mc_after.avar_lo, b.mc_after.avar_lo);
  EXPECT_EQ(a.mc_after.avar_hi, b.mc_after.avar_hi);
  EXPECT_EQ(a.mc_before.gaps, b.mc_before.gaps);
  EXPECT_EQ(a.before.gap, b.before.gap);
}

// Without the given model's replicas (analyze's modelling) the corrected model, the effects named
// and the verdict's replicas are the same, with a hidden effect (the model corrected) and with a
// complete model (not corrected: mc_after is then simulated rather than copied from mc_before).
// 19 replicas, so that a model beyond noise also takes the verdict's round.
TEST(Diagnose, GivenReplicasChangeNothingElse) {
  auto hidden = test::base_model();
  hidden.terms.Q = 3e-4;
  for (const auto& truth : {hidden, test::base_model()}) {
    kernels::DiagnoseOptions off;
    off.mc_given = false;
    const auto a = test::run_scenario(truth, test::base_model(), 5, 19);
    const auto b = test::run_scenario(truth, test::base_model(), 5, 19, 0, off);
    EXPECT_EQ(a.mc_before.replicas, 19);
    EXPECT_EQ(b.mc_before.replicas, 0);
    EXPECT_TRUE(b.mc_before.gaps.empty());
    EXPECT_TRUE(b.mc_before.avar_lo.empty());
    EXPECT_EQ(a.effects_named, b.effects_named);
    EXPECT_TRUE(a.model_after == b.model_after);
    EXPECT_EQ(a.after.avar_model, b.after.avar_model);
    EXPECT_EQ(a.after.gap, b.after.gap);
    EXPECT_EQ(a.mc_after.gaps, b.mc_after.gaps);
    EXPECT_EQ(a.mc_after.avar_lo, b.mc_after.avar_lo);
    EXPECT_EQ(a.mc_after.avar_hi, b.mc_after.avar_hi);
    EXPECT_EQ(a.gap_within_noise, b.gap_within_noise);
    EXPECT_EQ(a.notes, b.notes);
  }
}

TEST(Diagnose, GapFollowsTheContract) {
  // z = ln(2) / sqrt(2 / 8) = 1.386 at every tau: gap 1.386.
  const std::vector<double> meas{2.0, 4.0}, model{1.0, 2.0}, edf{8.0, 8.0};
  EXPECT_NEAR(kernels::diagnose_gap(meas, model, edf), std::log(2.0) / 0.5, 1e-12);
  EXPECT_THROW(kernels::diagnose_gap(meas, std::vector<double>{1.0}, edf), std::invalid_argument);
}

TEST(Diagnose, PsdWitnessFindsTheLine) {
  auto truth = test::base_model();
  truth.sinusoids.push_back({0.008, 0.5, 0.3});
  std::vector<double> y(60000);
  kernels::simulate_channel(truth, 3, 0, y, 1);
  const auto line = kernels::find_spectral_line(y, test::kRateHz, {}, 1e-4, 1);
  ASSERT_TRUE(line.found);
  // Within 3 Cramer-Rao sigmas plus the interpolation's bias, at most a tenth of a bin.
  EXPECT_NEAR(line.frequency_hz, 0.5, 3.0 * line.sigma_hz + 0.1 * line.resolution_hz);
  EXPECT_NEAR(line.amplitude, 0.008, 0.15 * 0.008);
  std::vector<double> w(60000);
  kernels::simulate_channel(test::base_model(), 3, 0, w, 1);
  EXPECT_FALSE(kernels::find_spectral_line(w, test::kRateHz, {}, 1e-4, 1).found);
}

// A real z accelerometer's noise (ADIS16405 imu6's corrected model, docs/diagnose.md): the
// boxcar filter, a narrow 0.56 Hz resonance, flicker, random walk and a weak 1.69 Hz resonance.
kernels::ChannelSpec accelerometer_truth() {
  kernels::ChannelSpec s;
  s.rate_hz = test::kRateHz;
  s.terms.N = 0.00048;
  s.terms.K = 2.8e-5;
  s.terms.B = 0.000277;
  s.lowpass.taps = 1.16;
  s.resonances = {{0.0005, 0.5646, 957.0, 0.0, 0.0}, {0.000136, 1.693, 1060.0, 0.0, 0.0}};
  return s;
}

// After the pruning removes an effect the rounds resume, and the corrected model, diagnosed
// again, names nothing. On seed 4 the rounds name a quantization beside the one-pole filter they
// chose first; the final refit, the filter searched again, takes it to the boxcar and the
// quantization away, and the resumed round names the slow hump (a flicker the given model
// lacks) that the quantization had hidden. Before the rounds resumed, the corrected model
// lacked it and its own diagnosis named more.
TEST(Diagnose, RoundsResumeAfterARemoval) {
  kernels::ChannelSpec given;
  given.rate_hz = test::kRateHz;
  given.terms.N = 0.00046;
  given.terms.K = 3e-5;
  std::vector<double> y(200000);
  kernels::simulate_channel(accelerometer_truth(), 4, 0, y, 1);
  kernels::DiagnoseOptions opt;
  opt.mc_replicas = 0;
  const auto d = kernels::diagnose(y, test::kRateHz, given, opt);
  EXPECT_TRUE(has_note(d, "quantization removed after the final refit"));
  EXPECT_TRUE(has_note(d, "the rounds resumed after the removal and named markov"));
  EXPECT_EQ(std::count(d.effects_named.begin(), d.effects_named.end(), Effect::Quantization), 0);
  const auto again = kernels::diagnose(y, test::kRateHz, d.model_after, opt);
  EXPECT_TRUE(again.effects_named.empty());
}

TEST(Diagnose, DumbInputs) {
  const std::vector<double> short_rec(20, 1.0);
  EXPECT_THROW(kernels::diagnose(short_rec, 100.0, test::base_model()), std::invalid_argument);
  std::vector<double> y(4000);
  kernels::simulate_channel(test::base_model(), 1, 0, y, 1);
  kernels::ChannelSpec empty;  // predicts no noise at all
  EXPECT_THROW(kernels::diagnose(y, 100.0, empty), std::invalid_argument);
  kernels::ChannelSpec bad = test::base_model();
  bad.terms.N = -1.0;
  EXPECT_THROW(kernels::diagnose(y, 100.0, bad), std::invalid_argument);
  kernels::DiagnoseOptions opt;
  opt.band_alpha = 2.0;
  EXPECT_THROW(kernels::diagnose(y, 100.0, test::base_model(), opt), std::invalid_argument);
  for (const int max_effects : {0, kernels::kMaxEffects + 1}) {
    kernels::DiagnoseOptions capped;
    capped.max_effects = max_effects;
    EXPECT_THROW(kernels::diagnose(y, 100.0, test::base_model(), capped), std::invalid_argument)
        << max_effects;
  }
  EXPECT_EQ(kernels::parse_effect("random_walk"), Effect::RandomWalk);
  EXPECT_FALSE(kernels::parse_effect("drift").has_value());
}

}  // namespace
}  // namespace allanlot
