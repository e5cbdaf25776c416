// The data-quality screen (kernels/quality/quality.hpp, docs/quality.md): each flag fires on data
// made to show it and on nothing else, the thresholds sit where the documentation puts them,
// the report is the same for any thread count, and dumb inputs give the documented result.
// The false-flag rate on clean simulated channels is tests/kernels/test_quality_clean.cpp's.
#include "kernels/quality/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace allanlot {
namespace {

using kernels::QualityInput;
using kernels::QualityOptions;
using kernels::QualityReport;
using kernels::screen_quality;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<double> white(std::size_t n, double sigma, unsigned seed, double offset = 0) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<double> x(n);
  for (double& v : x)
    v = offset + g(gen);
  return x;
}

// White noise of `sigma_lsb` steps around `mean_lsb`, rounded to whole steps of `lsb`, as an
// integer ADC delivers it after scaling.
std::vector<double> quantized(std::size_t n, double sigma_lsb, double mean_lsb, double lsb,
                              unsigned seed) {
  std::vector<double> x = white(n, sigma_lsb, seed, mean_lsb);
  for (double& v : x)
    v = std::round(v) * lsb;
  return x;
}

QualityReport run(const std::vector<double>& x, int threads = 1) {
  QualityInput in;
  in.samples = x;
  QualityOptions opt;
  opt.threads = threads;
  return screen_quality(in, opt);
}

TEST(Quality, CleanWhiteNoiseRaisesNoFlag) {
  const QualityReport r = run(white(200'000, 1.0, 1));
  EXPECT_EQ(r.flags, "");
  EXPECT_EQ(r.n_samples, 200'000);
  EXPECT_EQ(r.longest_run, 1);
  EXPECT_LE(r.stuck_run, 4);  // not a single repeat: four equal samples are already suspect
  EXPECT_GT(r.max_spike_sigmas, 3.0);
  EXPECT_LT(r.max_spike_sigmas, 8.0);
}

TEST(Quality, GapsAreCountedAsRunsAndMissingSamples) {
  std::vector<double> x = white(10'000, 1.0, 2);
  for (int i = 500; i < 520; ++i)
    x[i] = kNaN;
  x[7000] = kNaN;
  const QualityReport r = run(x);
  EXPECT_EQ(r.n_gap_runs, 2);
  EXPECT_EQ(r.n_missing, 21);
  EXPECT_EQ(r.first_gap, 500);
  EXPECT_EQ(r.flags, "gaps");
}

TEST(Quality, TimeStampCountsPassThrough) {
  const std::vector<double> x = white(1000, 1.0, 3);
  QualityInput in;
  in.samples = x;
  in.time.n_duplicate = 2;
  in.time.first_duplicate = 17;
  in.time.n_decreasing = 1;
  in.time.first_decreasing = 40;
  const QualityReport r = screen_quality(in);
  EXPECT_EQ(r.n_duplicate_times, 2);
  EXPECT_EQ(r.first_duplicate_time, 17);
  EXPECT_EQ(r.n_decreasing_times, 1);
  EXPECT_EQ(r.first_decreasing_time, 40);
  EXPECT_EQ(r.flags, "time_stamps");
}

TEST(Quality, SaturationAtTheStorageLimits) {
  const double lsb = 0.01;
  std::vector<double> x = quantized(50'000, 3.0, 0.0, lsb, 4);
  QualityInput in;
  in.storage_min = -32768 * lsb;
  in.storage_max = 32767 * lsb;
  for (int i = 20'000; i < 20'005; ++i)  // a shock clipped for five samples
    x[i] = *in.storage_max;
  x[30'000] = x[30'001] = *in.storage_min;  // two samples at the limit: not a run of three
  in.samples = x;
  const QualityReport r = screen_quality(in);
  EXPECT_EQ(r.n_saturated_runs, 1);
  EXPECT_EQ(r.n_saturated_samples, 5);
  EXPECT_EQ(r.first_saturated, 20'000);
  EXPECT_NE(r.flags.find("saturation"), std::string::npos);
}

TEST(Quality, SaturationAtTheRecordsOwnExtremeWhenPiledUp) {
  // Floating storage, no limits known: a signal clipped at 2.5 (the converter's range) piles
  // samples up on the record's maximum.
  std::vector<double> x = white(50'000, 1.0, 5);
  for (int i = 10'000; i < 10'400; ++i)
    x[i] += 3.0;
  for (double& v : x)
    v = std::min(v, 2.5);
  const QualityReport r = run(x);
  EXPECT_GT(r.n_saturated_runs, 0);
  EXPECT_GE(r.first_saturated, 10'000);
  EXPECT_LT(r.first_saturated, 10'400);
  EXPECT_NE(r.flags.find("saturation"), std::string::npos);
}

TEST(Quality, AQuantizedSensorsOwnExtremeIsNotSaturation) {
  // Noise of 1 step: the extreme values are hit a few times, and a run of three at the
  // maximum may occur, but the tail thins out: no pile-up. Noise of 0.1 step: two values, the
  // minimum the most frequent one, but a record spanning a few steps is not judged.
  for (const double sigma : {1.0, 0.1})
    for (unsigned seed = 10; seed < 20; ++seed) {
      const QualityReport r = run(quantized(200'000, sigma, 0.3, 1.0, seed));
      EXPECT_EQ(r.n_saturated_runs, 0) << "sigma " << sigma << ", seed " << seed;
      EXPECT_EQ(r.flags, "") << "sigma " << sigma << ", seed " << seed;
    }
}

TEST(Quality, StuckOutputInFloatingData) {
  std::vector<double> x = white(100'000, 1.0, 6);
  for (int i = 40'000; i < 40'050; ++i)
    x[i] = x[40'000];
  const QualityReport r = run(x);
  EXPECT_EQ(r.longest_run, 50);
  EXPECT_EQ(r.longest_run_start, 40'000);
  EXPECT_EQ(r.n_stuck_runs, 1);
  EXPECT_EQ(r.first_stuck, 40'000);
  EXPECT_EQ(r.flags, "stuck");
}

TEST(Quality, StuckOutputInQuantizedDataAgainstItsOwnStatistics) {
  // Noise of 0.5 steps: a third of the samples repeat their predecessor, and natural runs of
  // 10 occur; a run of 80 does not.
  std::vector<double> x = quantized(300'000, 0.5, 0.0, 1.0, 7);
  const QualityReport clean = run(x);
  EXPECT_EQ(clean.flags, "");
  EXPECT_GT(clean.p_equal, 0.2);
  EXPECT_GT(clean.stuck_run, clean.longest_run);
  for (int i = 100'000; i < 100'080; ++i)
    x[i] = 1.0;
  for (int i = 200'000; i < 200'080; ++i)  // a second stretch does not hide the first
    x[i] = 0.0;
  const QualityReport r = run(x);
  EXPECT_EQ(r.n_stuck_runs, 2);
  EXPECT_GE(r.first_stuck, 99'990);
  EXPECT_LE(r.first_stuck, 100'000);
  EXPECT_NE(r.flags.find("stuck"), std::string::npos);
}

TEST(Quality, ConstantRecordIsStuckNotSaturated) {
  const QualityReport r = run(std::vector<double>(10'000, 4.0));
  EXPECT_EQ(r.n_stuck_runs, 1);
  EXPECT_EQ(r.n_saturated_runs, 0);
  EXPECT_EQ(r.n_spikes, 0);
  EXPECT_EQ(r.flags, "stuck");
}

TEST(Quality, SpikesBeyondTenRobustSigmas) {
  std::vector<double> x = white(100'000, 1.0, 8, 9.81);
  x[1000] += 20;
  x[50'000] -= 15;
  for (int i = 70'000; i < 70'003; ++i)  // a burst of three
    x[i] += 30;
  x[80'000] += 7;  // 7 sigma: large, but not a spike
  const QualityReport r = run(x);
  EXPECT_EQ(r.n_spikes, 5);
  EXPECT_EQ(r.first_spike, 1000);
  EXPECT_GT(r.max_spike_sigmas, 25);
  EXPECT_EQ(r.flags, "spikes");
}

TEST(Quality, SpikesAtTheEndsAndBesideGapsAreFound) {
  // Windows are truncated at the ends and thinned by gaps; a spike there is still judged
  // against the median of what the window holds.
  std::vector<double> x = white(20'000, 1.0, 13);
  x[0] += 30;
  x[19'999] -= 30;
  for (int i = 8'000; i < 8'010; ++i)
    x[i] = kNaN;
  x[8'010] += 30;
  x[7'999] -= 30;
  const QualityReport r = run(x);
  EXPECT_EQ(r.n_spikes, 4);
  EXPECT_EQ(r.first_spike, 0);
  EXPECT_EQ(r.flags, "gaps;spikes");
}

TEST(Quality, RandomWalkAndStepsAreNotSpikes) {
  // A random walk ten times the white noise per step, and a bias jump of 50 sigma.
  std::vector<double> x = white(200'000, 1.0, 9);
  const std::vector<double> steps = white(x.size(), 10.0, 10);
  double walk = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    walk += steps[i];
    x[i] += walk + (i >= 120'000 ? 50.0 : 0.0);
  }
  const QualityReport r = run(x);
  EXPECT_EQ(r.n_spikes, 0) << "max " << r.max_spike_sigmas;
}

TEST(Quality, OneStepFlickerOfAQuietQuantizedSensorIsNotASpike) {
  // Noise of 0.1 steps: nearly every residual is 0, the MAD is 0, and the floor keeps the
  // occasional one-step change from counting as a spike.
  const QualityReport r = run(quantized(100'000, 0.1, 0.45, 0.001, 11));
  EXPECT_EQ(r.n_spikes, 0);
  EXPECT_LT(r.max_spike_sigmas, 3.0);
}

TEST(Quality, SameReportForAnyThreadCount) {
  std::vector<double> x = quantized(700'001, 2.0, 0.0, 0.5, 12);
  for (int i = 65'530; i < 65'545; ++i)  // a gap across a chunk boundary of two threads
    x[i] = kNaN;
  for (int i = 131'068; i < 131'300; ++i)  // a stuck run across one of 7 threads' boundaries
    x[i] = 1.75;
  x[400'000] -= 100;
  for (int i = 500'000; i < 500'020; ++i)
    x[i] = 40.0;  // the record's maximum, piled up
  const QualityReport one = run(x, 1);
  EXPECT_EQ(one.flags, "gaps;saturation;stuck;spikes");
  EXPECT_EQ(one.first_stuck, 131'068);
  for (const int threads : {2, 3, 7})
    EXPECT_EQ(run(x, threads), one) << threads << " threads";
}

TEST(Quality, DumbInputs) {
  EXPECT_EQ(run({}).flags, "");
  EXPECT_EQ(run({1.0}).longest_run, 1);
  const QualityReport nan = run(std::vector<double>(100, kNaN));
  EXPECT_EQ(nan.n_missing, 100);
  EXPECT_EQ(nan.n_gap_runs, 1);
  EXPECT_EQ(nan.longest_run, 0);
  EXPECT_EQ(nan.flags, "gaps");
  QualityInput in;
  QualityOptions opt;
  opt.spike_window = 30;
  EXPECT_THROW(screen_quality(in, opt), std::invalid_argument);
  opt = {};
  opt.spike_sigmas = 0;
  EXPECT_THROW(screen_quality(in, opt), std::invalid_argument);
  opt = {};
  opt.saturation_run = 1;
  EXPECT_THROW(screen_quality(in, opt), std::invalid_argument);
  opt = {};
  opt.stuck_expected = 1;
  EXPECT_THROW(screen_quality(in, opt), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
