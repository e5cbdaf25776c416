// Clock frequency recorded in Hz (docs/formats.md "Units and conventions"): with
// --nominal-frequency F it is read as fractional frequency y = (f - F) / F and gives the
// deviations of the same recording in fractional units; without it, a usage error (exit 2)
// naming the channel, before any work.
#include "io/results.hpp"
#include "kernels/model/units.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

// F = 2^23 Hz and y on a grid of 2^-40: f = F (1 + y) = F + k 2^-17 is exact in a double, so the
// Hz recording and the fractional one hold the same clock, digit for digit.
constexpr double kNominalHz = 8388608.0;
constexpr double kStep = 0x1p-40;

// White FM plus random-walk FM, in units of kStep (|k| well below 2^30).
std::vector<double> clock_steps(std::size_t n) {
  std::mt19937_64 gen(51);
  std::normal_distribution<double> white(0.0, 1000.0), walk(0.0, 30.0);
  std::vector<double> k(n);
  double rw = 0;
  for (double& v : k) {
    rw += std::round(walk(gen));
    v = std::round(white(gen)) + rw;
  }
  return k;
}

void write_clock(const fs::path& file, const std::vector<double>& v, const std::string& units) {
  test::H5Fixture f(file);
  f.group("/clock");
  f.attr("/clock", "sample_rate_hz", 1.0);
  f.dataset("/clock/freq", v, H5T_IEEE_F64LE);
  f.attr("/clock/freq", "units", units);
  f.attr("/clock/freq", "data_type", "rate");
}

io::RecordingResult analyze(const fs::path& input, const fs::path& out, const std::string& extra) {
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q --no-fit --no-psd --stats oadev,mdev,hdev,tdev " +
                            extra + " -o " + out.string() + " " + input.string(),
                        &text),
            0)
      << text;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().string().ends_with(".allan.h5")) return io::read_results(e.path());
  ADD_FAILURE() << "no results file in " << out;
  return {};
}

TEST(FrequencyHz, VocabularyAndExactNormalisation) {
  const auto hz = kernels::units::parse_channel_units("Hz");
  ASSERT_TRUE(hz);
  EXPECT_EQ(hz->canonical, "1");
  EXPECT_TRUE(hz->per_nominal);
  EXPECT_FALSE(kernels::units::parse_channel_units("ppb")->per_nominal);
  // f - F is exact near F: a 1e-13 offset of a 10 MHz oscillator keeps its digits, which
  // f / F - 1 would not.
  const double f = 1e7 + 1e-6;
  EXPECT_EQ(kernels::units::to_fractional_frequency(f, 1e7), (f - 1e7) / 1e7);
  EXPECT_NEAR(kernels::units::to_fractional_frequency(f, 1e7), 1e-13, 1e-13 * 1e-3);
}

TEST(FrequencyHz, SameDeviationsAsFractionalFrequency) {
  const fs::path d = test::fresh_dir("frequency_hz");
  const auto k = clock_steps(4000);
  std::vector<double> f(k.size()), y(k.size());
  for (std::size_t i = 0; i < k.size(); ++i) {
    y[i] = k[i] * kStep;
    f[i] = kNominalHz + kNominalHz * y[i];
    ASSERT_EQ((f[i] - kNominalHz) / kNominalHz, y[i]) << "the fixture is not exact at " << i;
  }
  write_clock(d / "hz.h5", f, "Hz");
  write_clock(d / "y.h5", y, "1");
  fs::create_directories(d / "hz_out");
  fs::create_directories(d / "y_out");
  char nominal[64];
  std::snprintf(nominal, sizeof nominal, "--nominal-frequency %.17g", kNominalHz);
  const auto a = analyze(d / "hz.h5", d / "hz_out", nominal);
  const auto b = analyze(d / "y.h5", d / "y_out", "");
  ASSERT_EQ(a.channels.size(), 1u);
  ASSERT_EQ(b.channels.size(), 1u);
  EXPECT_EQ(a.channels[0].units, "1");
  ASSERT_EQ(a.channels[0].stats.size(), 4u);
  ASSERT_EQ(a.channels[0].stats.size(), b.channels[0].stats.size());
  for (std::size_t s = 0; s < a.channels[0].stats.size(); ++s) {
    const auto& [name, x] = a.channels[0].stats[s];
    const auto& r = b.channels[0].stats[s].second;
    SCOPED_TRACE(name);
    ASSERT_EQ(x.m, r.m);
    ASSERT_GT(x.size(), 5u);
    for (std::size_t i = 0; i < x.size(); ++i)
      EXPECT_NEAR(x.dev[i], r.dev[i], 1e-12 * r.dev[i]) << "m = " << x.m[i];
  }
}

TEST(FrequencyHz, WithoutNominalFrequencyAUsageErrorNamingTheChannel) {
  const fs::path d = test::fresh_dir("frequency_hz_usage");
  write_clock(d / "hz.h5", std::vector<double>(100, kNominalHz), "Hz");
  std::string out;
  EXPECT_EQ(run_command(binary() + " analyze -q -o " + (d / "out").string() + " " +
                            (d / "hz.h5").string(),
                        &out),
            2);
  EXPECT_NE(out.find("/clock/freq"), std::string::npos) << out;
  EXPECT_NE(out.find("--nominal-frequency"), std::string::npos) << out;
  EXPECT_TRUE(!fs::exists(d / "out") || fs::is_empty(d / "out")) << "nothing is written";
  // A text column given in Hz on the command line: the option names the columns.
  {
    std::ofstream t(d / "f.csv");
    t << "time,freq\n0,8388608\n1,8388608\n";
  }
  EXPECT_EQ(run_command(binary() + " analyze -q --units 'freq=Hz' -o " + (d / "out").string() +
                            " " + (d / "f.csv").string(),
                        &out),
            2);
  EXPECT_NE(out.find("'freq'"), std::string::npos) << out;
  EXPECT_NE(out.find("--nominal-frequency"), std::string::npos) << out;
}

}  // namespace
}  // namespace allanlot
