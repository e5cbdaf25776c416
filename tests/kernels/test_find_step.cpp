// The step effect: a bias jump's Allan variance (kernels::step_avar_sampled)
// against a direct long-double evaluation of the simulated jump, and its time-domain witness
// (kernels::find_step) on null records of every noise kind, on jumps of a few rms, and on
// look-alikes (a spike, a ramp, a strong line).
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace allanlot {
namespace {

constexpr double kRate = 100.0;
constexpr std::size_t kSamples = 60000;  // 600 s

// The overlapping Allan variance of `y` at m, directly from its definition (NIST SP1065 eq.
// (11)) with long double sums: the naive reference.
long double direct_oavar(const std::vector<double>& y, std::int64_t m) {
  std::vector<long double> x(y.size() + 1, 0.0L);
  for (std::size_t k = 0; k < y.size(); ++k)
    x[k + 1] = x[k] + static_cast<long double>(y[k]);
  const auto n = static_cast<std::int64_t>(y.size());
  long double s = 0.0L;
  for (std::int64_t k = 0; k + 2 * m <= n; ++k) {
    const long double d =
        (x[static_cast<std::size_t>(k + 2 * m)] - 2.0L * x[static_cast<std::size_t>(k + m)] +
         x[static_cast<std::size_t>(k)]) /
        static_cast<long double>(m);
    s += d * d;
  }
  return s / (2.0L * static_cast<long double>(n - 2 * m + 1));
}

std::vector<double> simulate(const kernels::ChannelSpec& spec, std::uint64_t stream,
                             std::size_t n = kSamples) {
  std::vector<double> y(n);
  kernels::simulate_channel(spec, 4100, stream, y, 1);
  return y;
}

TEST(StepAvar, MatchesTheSimulatedJumpDirectly) {
  // A jump alone is deterministic: the simulator's samples (the part of the straddling sample
  // after the jump included) through the estimator's definition must give step_avar_sampled,
  // mid-record, near either end, between samples and on a sample's boundary.
  const std::size_t n = 5000;
  for (const double t : {0.005, 0.37, 12.345, 25.0, 37.77, 49.2, 49.995}) {
    kernels::ChannelSpec s;
    s.rate_hz = kRate;
    s.steps.push_back({-0.3, t});
    const std::vector<double> y = simulate(s, 1, n);
    for (const std::int64_t m : {1, 2, 7, 64, 333, 1250}) {
      const long double ref = direct_oavar(y, m);
      const double got = kernels::step_avar_sampled(s.steps[0], kRate, m, n);
      EXPECT_NEAR(got, static_cast<double>(ref), 1e-10 * static_cast<double>(ref) + 1e-300)
          << "time " << t << " m " << m;
      EXPECT_EQ(kernels::model_avar_sampled(s, m, n), got);
    }
  }
  // An unbounded record: no contribution; m beyond the record: an error.
  kernels::ChannelSpec s;
  s.rate_hz = kRate;
  s.steps.push_back({1.0, 10.0});
  EXPECT_EQ(kernels::model_avar_sampled(s, 16), 0.0);
  EXPECT_THROW(kernels::step_avar_sampled(s.steps[0], kRate, 100, 150), std::invalid_argument);
}

TEST(StepAvar, JumpsCloseTogetherHaveTheirCrossTerms) {
  // Two jumps within 2 m samples of each other (a bias excursion and its return, two jumps the
  // same way): the simulator's samples through the estimator's definition give
  // model_avar_sampled, whose share of the pair is no longer the sum of their two shares.
  const std::size_t n = 5000;
  for (const double second : {-0.3, 0.2}) {
    kernels::ChannelSpec s;
    s.rate_hz = kRate;
    s.steps.push_back({0.3, 12.345});
    s.steps.push_back({second, 14.0});
    const std::vector<double> y = simulate(s, 1, n);
    for (const std::int64_t m : {1, 2, 7, 64, 333, 1250}) {
      const long double ref = direct_oavar(y, m);
      const double got = kernels::model_avar_sampled(s, m, n);
      EXPECT_NEAR(got, static_cast<double>(ref), 1e-10 * static_cast<double>(ref) + 1e-300)
          << "second " << second << " m " << m;
    }
    // At m = 333 (the jumps 165 samples apart) the excursion gives far less than the two shares.
    if (second < 0) {
      EXPECT_LT(kernels::model_avar_sampled(s, 333, n),
                0.5 * (kernels::step_avar_sampled(s.steps[0], kRate, 333, n) +
                       kernels::step_avar_sampled(s.steps[1], kRate, 333, n)));
    }
  }
}

TEST(StepAvar, MidRecordClosedForm) {
  // Far from both ends the sum of the triangle's squares is (2 m^2 + 1) / (3 m).
  for (const std::int64_t m : {1, 3, 40, 512}) {
    const std::int64_t n = 100000;
    const double expect = (2.0 * m * m + 1.0) / (6.0 * m * (n - 2 * m + 1));
    EXPECT_NEAR(kernels::step_avar_sampled({1.0, 500.0}, kRate, m, n), expect, 1e-13 * expect);
  }
}

// The noises a witness must not mistake for a jump: the scenarios' white + flicker, random-walk
// dominated, white PM dominated (uncorrelated second differences: every window counts), a
// Gauss-Markov process, and a strong line.
std::vector<std::pair<std::string, kernels::ChannelSpec>> null_models() {
  std::vector<std::pair<std::string, kernels::ChannelSpec>> out;
  kernels::ChannelSpec base;
  base.rate_hz = kRate;
  base.terms.N = 0.01;
  base.terms.B = 0.003;
  out.emplace_back("white+flicker", base);
  auto rw = base;
  rw.terms.K = 0.01;
  out.emplace_back("random walk", rw);
  auto pm = base;
  pm.terms.Q = 0.01;
  out.emplace_back("white PM", pm);
  auto gm = base;
  gm.markovs.push_back({0.05, 2.0});
  out.emplace_back("gauss-markov", gm);
  auto line = base;
  line.sinusoids.push_back({0.05, 0.7, 0.0});
  out.emplace_back("sinusoid", line);
  return out;
}

TEST(FindStep, NullRecordsRarelyShowAJump) {
  // 5 noise kinds x 40 seeds at the default level 1e-3: expected false alarms at most 0.2 (the
  // test is conservative), and three or more would have probability 0.001 at the nominal
  // level. At a level of 0.2 the rate must stay at most 0.2 per record, for each kind (0.285:
  // its binomial 3 sigma over 40 seeds, 0.2 + 3 sqrt(0.2 0.8 / 40) = 0.39, is looser; measured
  // 0-3 of 40 per kind: the test is conservative, and the Gauss-Markov effect's smooth
  // windows, which the lag-1 correlation alone made 14 of 40, are in it).
  int alarms = 0;
  for (const auto& [name, spec] : null_models()) {
    int loose = 0;
    for (int seed = 0; seed < 40; ++seed) {
      const std::vector<double> y = simulate(spec, static_cast<std::uint64_t>(seed));
      const kernels::StepWitness w = kernels::find_step(y, kRate, {}, 1e-3);
      EXPECT_TRUE(w.searched);
      alarms += w.found ? 1 : 0;
      loose += w.p_value < 0.2 ? 1 : 0;
    }
    EXPECT_LE(loose, 0.285 * 40) << name;
    if (std::getenv("FIND_STEP_VERBOSE") != nullptr)
      std::printf("%-14s p < 0.2 on %d of 40\n", name.c_str(), loose);
  }
  EXPECT_LE(alarms, 2);
}

// A jump of about 8 rms of the differences of adjacent means at the best scale (0.045 against
// their rms 0.0053 at m = 1024, white + flicker of the scenarios) anywhere in the middle 80 % of
// the record, with or without a ramp or a strong line beside it.
TEST(FindStep, NamesAJumpOfAFewRmsWithItsTimeAndSize) {
  for (const char* beside : {"", "ramp", "sinusoid"}) {
    int found = 0;
    for (int seed = 0; seed < 20; ++seed) {
      kernels::ChannelSpec s = null_models()[0].second;
      if (std::string(beside) == "ramp") s.terms.R = 1.5e-4;
      if (std::string(beside) == "sinusoid") s.sinusoids.push_back({0.05, 0.7, 0.0});
      const double t = 60.0 + 24.0 * seed + 0.37;
      const double size = seed % 2 == 0 ? 0.045 : -0.045;
      s.steps.push_back({size, t});
      const std::vector<double> y = simulate(s, 100 + static_cast<std::uint64_t>(seed));
      const kernels::StepWitness w = kernels::find_step(y, kRate, {}, 1e-3);
      if (!w.found) continue;
      ++found;
      // The time to within its stated scale, the size to within 3 of its sigma.
      EXPECT_LE(std::abs(w.time_s - t), w.time_sigma_s) << beside << " seed " << seed;
      EXPECT_LE(std::abs(w.size - size), 3.0 * w.size_sigma) << beside << " seed " << seed;
      // Removing the named jump leaves nothing to find.
      const std::vector<kernels::Step> known{{w.size, w.time_s}};
      EXPECT_FALSE(kernels::find_step(y, kRate, known, 1e-3).found) << beside << " seed " << seed;
    }
    EXPECT_GE(found, 19) << beside;
  }
}

TEST(FindStep, ASpikeIsNotAJump) {
  // One sample 40 x the white noise's sample sd (0.1): the largest differences of adjacent
  // means by far, but a plateau of both signs rather than a triangle.
  int found = 0;
  for (int seed = 0; seed < 10; ++seed) {
    std::vector<double> y =
        simulate(null_models()[0].second, 200 + static_cast<std::uint64_t>(seed));
    y[12345 + 977 * static_cast<std::size_t>(seed)] += 4.0;
    found += kernels::find_step(y, kRate, {}, 1e-3).found ? 1 : 0;
  }
  EXPECT_EQ(found, 0);
}

TEST(FindStep, AKnockIsNotAJump) {
  // One second (100 samples) of a burst 25 x the white noise's sample sd, zero mean: a large
  // difference of means at the smallest scales that halves with each doubling, as the real
  // imu4 record's knock at 4046 s does.
  int found = 0;
  for (int seed = 0; seed < 10; ++seed) {
    std::vector<double> y =
        simulate(null_models()[0].second, 300 + static_cast<std::uint64_t>(seed));
    std::vector<double> burst =
        simulate(null_models()[0].second, 400 + static_cast<std::uint64_t>(seed), 100);
    const std::size_t at = 20000 + 1500 * static_cast<std::size_t>(seed);
    double mean = 0.0;
    for (const double v : burst)
      mean += v / 100.0;
    for (std::size_t i = 0; i < 100; ++i)
      y[at + i] += 25.0 * (burst[i] - mean);
    found += kernels::find_step(y, kRate, {}, 1e-3).found ? 1 : 0;
  }
  EXPECT_EQ(found, 0);
}

TEST(FindStep, NoSearchOnGapsOrShortRecords) {
  std::vector<double> y = simulate(null_models()[0].second, 7, 1000);
  y[500] = std::nan("");
  EXPECT_FALSE(kernels::find_step(y, kRate, {}, 1e-3).searched);
  EXPECT_FALSE(kernels::find_step(std::vector<double>(50, 1.0), kRate, {}, 1e-3).searched);
  EXPECT_THROW(kernels::find_step(y, 0.0, {}, 1e-3), std::invalid_argument);
  EXPECT_THROW(kernels::find_step(y, kRate, {}, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
