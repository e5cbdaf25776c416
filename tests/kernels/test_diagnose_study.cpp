// The seed study behind the detection and false-alarm rates quoted in docs/diagnose.md: every
// hidden-effect scenario at three levels (test::kLevels), the complete model (null case) and
// the wrong-coefficient case over many seeds. Disabled by default (about two minutes per 10 seeds
// of one level's scenarios on one core); run with
//   test_kernels_diagnose_study --gtest_also_run_disabled_tests
// and DIAGNOSE_STUDY_SEEDS=N (default 20) seeds per scenario; DIAGNOSE_STUDY_ONLY=TEXT keeps
// the scenarios whose name contains TEXT (e.g. "ramp/weak"), DIAGNOSE_STUDY_LEVEL=LEVEL keeps
// one level, DIAGNOSE_STUDY_VERBOSE=1 prints every seed. DIAGNOSE_STUDY_OWN_REPLICAS=1 gives each
// record its own replicas (the Monte Carlo seed from the record's), so that the rate at which a
// complete model's record is beyond its replicas' p95 is averaged over replica sets; by default
// every record of one model shares the replica set of seed 7, as diagnose's default, whose p95
// is one draw of a threshold.
#include "kernels/test_diagnose_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using kernels::Effect;

bool names_exactly(const kernels::Diagnosis& d, std::vector<Effect> want) {
  std::vector<Effect> got = d.effects_named;
  std::sort(got.begin(), got.end());
  std::sort(want.begin(), want.end());
  return got == want;
}

std::string named(const kernels::Diagnosis& d) {
  std::string s;
  for (const Effect e : d.effects_named) {
    if (!s.empty()) s += ',';
    s += kernels::effect_name(e);
  }
  return s.empty() ? "-" : s;
}

double param(const kernels::Diagnosis& d, Effect e, const std::string& key) {
  for (std::size_t i = 0; i < d.effects_named.size(); ++i)
    if (d.effects_named[i] == e)
      for (const auto& p : d.effect_parameters[i])
        if (p.name == key) return p.value;
  return std::nan("");
}

TEST(DiagnoseStudy, DISABLED_DetectionAndFalseAlarmRates) {
  const char* env = std::getenv("DIAGNOSE_STUDY_SEEDS");
  const int seeds = env ? std::max(1, std::atoi(env)) : 20;
  const bool verbose = std::getenv("DIAGNOSE_STUDY_VERBOSE") != nullptr;
  kernels::DiagnoseOptions opt;
  const bool own_replicas = std::getenv("DIAGNOSE_STUDY_OWN_REPLICAS") != nullptr;
  std::printf("scenario                        exact  rate   gap_after(median)  within_noise  "
              "f_err_max  tau_c_err_max\n");
  // Every hidden-effect scenario at each level (DIAGNOSE_STUDY_LEVEL=weak|medium|strong keeps
  // one), then the cases without a level.
  const char* level_only = std::getenv("DIAGNOSE_STUDY_LEVEL");
  std::vector<test::Scenario> scenarios;
  for (const auto& level : test::kLevels)
    if (!level_only || std::string(level_only) == level.name)
      for (const auto& s : test::hidden_scenarios())
        scenarios.push_back(test::at_level(s, level));
  scenarios.push_back({"null", test::base_model(), test::base_model(), {}});
  {
    // The sensor's filter: first order at 15 Hz, and a boxcar of 1.5 samples.
    auto t = test::base_model();
    t.lowpass.cutoff_hz = 15.0;
    scenarios.push_back({"lowpass_15hz", t, test::base_model(), {Effect::Lowpass}});
    t.lowpass = {};
    t.lowpass.taps = 1.5;
    scenarios.push_back({"lowpass_taps1.5", t, test::base_model(), {Effect::Lowpass}});
  }
  {
    auto g = test::base_model();
    g.terms.N *= 1.3;
    scenarios.push_back({"wrong_N", test::base_model(), g, {}});
  }
  const char* only = std::getenv("DIAGNOSE_STUDY_ONLY");
  for (const auto& s : scenarios) {
    if (only && s.name.find(only) == std::string::npos) continue;
    int exact = 0, within = 0, wrong_flag = 0, phantom = 0, given_beyond = 0;
    double f_err = 0, tc_err = 0;
    std::vector<double> gaps;
    for (int seed = 1; seed <= seeds; ++seed) {
      // A seed far from the records' (1001 ...), so no replica is the record itself.
      if (own_replicas) opt.mc_seed = 1000000007ULL + static_cast<std::uint64_t>(seed);
      const auto d = test::run_scenario(s.truth, s.given, 1000 + seed, 20, 0, opt);
      exact += names_exactly(d, s.hidden) ? 1 : 0;
      // The given model's own verdict, before anything is named or re-estimated: the calibration
      // of the verdict where the given model is the truth (null case).
      given_beyond += kernels::within_noise(d.before.gap, d.mc_before) ? 0 : 1;
      within += d.gap_within_noise ? 1 : 0;
      wrong_flag += d.coefficients_wrong ? 1 : 0;
      gaps.push_back(d.after.gap);
      // Phantoms: an effect named twice (two sinusoids or markovs are allowed only
      // as distinct instances) or named with a zero size.
      for (std::size_t i = 0; i < d.effects_named.size(); ++i) {
        const bool twice =
            std::count(d.effects_named.begin(), d.effects_named.end(), d.effects_named[i]) > 1;
        const bool zero = !(std::abs(d.effect_parameters[i].front().value) > 0.0);  // signed step
        phantom += twice || zero ? 1 : 0;
      }
      if (!s.truth.sinusoids.empty()) {
        const double f = param(d, Effect::Sinusoid, "frequency_hz");
        if (std::isfinite(f))
          f_err = std::max(f_err, std::abs(f / s.truth.sinusoids[0].frequency_hz - 1.0));
      }
      if (!s.truth.resonances.empty()) {
        const double f = param(d, Effect::Resonance, "frequency_hz");
        if (std::isfinite(f))
          f_err = std::max(f_err, std::abs(f / s.truth.resonances[0].frequency_hz - 1.0));
      }
      if (!s.truth.markovs.empty()) {
        const double t = param(d, Effect::Markov, "tau_c_s");
        if (std::isfinite(t))
          tc_err = std::max(tc_err, std::abs(t / s.truth.markovs[0].tau_c_s - 1.0));
      }
      if (verbose) {
        std::printf("  %s seed %d: named %s gap %.3f -> %.3f (p95 %.3f) neff %.1f wrong %d\n",
                    s.name.c_str(), seed, named(d).c_str(), d.before.gap, d.after.gap,
                    d.mc_after.gap_p95, d.n_eff, d.coefficients_wrong ? 1 : 0);
        for (const auto& note : d.notes)
          std::printf("    %s\n", note.c_str());
        for (const auto& it : d.iterations)
          for (const auto& c : it.candidates)
            if (c.effect == it.effect)
              std::printf("    round %s: %+.1f %s\n",
                          std::string(kernels::effect_name(it.effect)).c_str(), c.delta_ic,
                          c.note.c_str());
      }
    }
    std::sort(gaps.begin(), gaps.end());
    std::printf("%-30s %3d/%-3d %5.2f  %8.3f           %3d/%-3d      %7.4f    %7.4f   "
                "(coefficients_wrong %d, phantoms %d, given model beyond its p95 %d)\n",
                s.name.c_str(), exact, seeds, static_cast<double>(exact) / seeds,
                gaps[gaps.size() / 2], within, seeds, f_err, tc_err, wrong_flag, phantom,
                given_beyond);
  }
}

}  // namespace
}  // namespace allanlot
