// The PSD witness of a narrowband process (kernels/diagnose/find_narrowband.cpp): a periodogram
// peak wider than a line is no sinusoid's witness, and its resonance is measured on the
// periodogram with honest uncertainties; a line stays a line, and white noise shows no broad
// peak. Simulated records of the resonance the simulator draws (the AR(2) of
// kernels/simulate/resonance.hpp), 600 s at 100 Hz: the bins are 1/600 Hz.
#include "kernels/diagnose/internal.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace allanlot {
namespace {

using namespace kernels::diagnose_detail;

constexpr double kRate = 100.0;
constexpr std::size_t kSamples = 60000;

std::vector<double> record(const kernels::ChannelSpec& truth, std::uint64_t seed) {
  std::vector<double> y(kSamples);
  kernels::simulate_channel(truth, seed, 0, y, 1);
  return y;
}

// White noise N = 0.01 (one-sided PSD 2e-4 u^2/Hz) and a resonance of sd sigma: at its peak,
// 2 sigma^2 q / (pi f0), 32 times the background for sigma = 0.1, q = 100 at 2 Hz.
kernels::ChannelSpec with_resonance(double sigma, double f0, double q) {
  kernels::ChannelSpec s;
  s.rate_hz = kRate;
  s.terms.N = 0.01;
  s.resonances.push_back({sigma, f0, q});
  return s;
}

// A q = 100 peak at 2 Hz is 12 bins wide at half power: the line witness notes it as wider than a
// line and names no sinusoid, and its fit recovers f0, q and sigma. Over 20 records the errors
// in units of the fit's own sigmas have an rms near 1: the sigmas come from the Fisher
// information of Whittle's likelihood, inflated for the Hann window's correlation of neighbouring
// bins; for 20 draws of a unit normal the rms lies in [0.6, 1.4] with probability above 0.99
// (chi-square of 20 degrees of freedom: 7.4 to 39), and the band allows as much again for the
// asymptotics of the fit.
TEST(FindNarrowband, APeakWiderThanALineIsMeasuredAsAResonance) {
  const kernels::ChannelSpec truth = with_resonance(0.1, 2.0, 100.0);
  double ss_f = 0.0, ss_q = 0.0, ss_s = 0.0;
  constexpr int kRecords = 20;
  for (int r = 0; r < kRecords; ++r) {
    const std::vector<double> y = record(truth, 40 + static_cast<std::uint64_t>(r));
    const kernels::SpectralLine line = kernels::find_spectral_line(y, kRate, {}, 1e-4, 1);
    EXPECT_FALSE(line.found) << "record " << r;
    ASSERT_NEAR(line.wide_hz, 2.0, 0.05) << "record " << r;
    const auto& nb = line.narrowband;
    ASSERT_TRUE(nb.found) << "record " << r;
    ss_f += std::pow((nb.frequency_hz - 2.0) / nb.frequency_sigma, 2);
    ss_q += std::pow((nb.q - 100.0) / nb.q_sigma, 2);
    ss_s += std::pow((nb.sigma - 0.1) / nb.sigma_sigma, 2);
  }
  for (const double ss : {ss_f, ss_q, ss_s}) {
    EXPECT_GT(std::sqrt(ss / kRecords), 0.4);
    EXPECT_LT(std::sqrt(ss / kRecords), 1.8);
  }
}

// A line's power stays in the Hann window's main lobe: it is found as a line, with no width.
TEST(FindNarrowband, ALineIsNotWide) {
  kernels::ChannelSpec truth = with_resonance(0.0, 2.0, 100.0);
  truth.resonances.clear();
  truth.sinusoids.push_back({0.02, 3.3, 0.0});
  const std::vector<double> y = record(truth, 5);
  const kernels::SpectralLine line = kernels::find_spectral_line(y, kRate, {}, 1e-4, 1);
  EXPECT_TRUE(line.found);
  EXPECT_EQ(line.wide_hz, 0.0);
  EXPECT_FALSE(line.narrowband.found);
}

// A broad peak (q = 10 at 10 Hz, 1 Hz wide: no bin stands out) is measured around the frequency
// the Allan curve gives, even a tenth off; white noise alone shows none at 1e-4.
TEST(FindNarrowband, ABroadPeakIsMeasuredAroundTheCurvesFrequency) {
  const std::vector<double> y = record(with_resonance(0.08, 10.0, 10.0), 9);
  const kernels::PsdResult psd = full_periodogram(y, kRate, 1);
  const kernels::SpectralLine::Narrowband nb = fit_broad(psd, 11.0, 1e-4);
  ASSERT_TRUE(nb.found);
  EXPECT_NEAR(nb.frequency_hz, 10.0, 4.0 * nb.frequency_sigma);
  EXPECT_NEAR(nb.q, 10.0, 4.0 * nb.q_sigma);
  EXPECT_NEAR(nb.sigma, 0.08, 4.0 * nb.sigma_sigma);
  int false_alarms = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const std::vector<double> w = record(with_resonance(0.0, 10.0, 10.0), seed);
    false_alarms += fit_broad(full_periodogram(w, kRate, 1), 10.0, 1e-4).found ? 1 : 0;
  }
  EXPECT_EQ(false_alarms, 0);
}

}  // namespace
}  // namespace allanlot
