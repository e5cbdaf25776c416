// The one vocabulary of units (kernels/model/units.hpp) as a user meets it: a recording's units
// in the spellings of IMU logs and clock files are read as the canonical unit, clock units that
// scale are scaled, and a unit outside the vocabulary is kept with one warning per file.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

std::vector<double> white(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  for (auto& x : v)
    x = g(rng);
  return v;
}

const io::ChannelResult& channel(const io::RecordingResult& r, const std::string& path) {
  for (const auto& c : r.channels)
    if (c.path == path) return c;
  throw std::runtime_error("no channel " + path);
}

TEST(UnitsVocabulary, SpellingsAreReadAsTheCanonicalUnits) {
  const auto dir = test::fresh_dir("units_vocabulary");
  const auto y = white(20000, 3);
  {
    test::H5Fixture f(dir / "u.h5");
    for (const char* ch : {"gyro_dps", "accel_ms2", "clock_1", "clock_ppb", "volts_a", "volts_b"})
      f.dataset(std::string("/") + ch, y, H5T_IEEE_F64LE);
    f.attr("/", "sample_rate_hz", 10.0);
    f.attr("/gyro_dps", "units", "dps");
    f.attr("/accel_ms2", "units", "m/s2");
    f.attr("/clock_1", "units", "1");
    f.attr("/clock_ppb", "units", "ppb");
    f.attr("/volts_a", "units", "furlong");
    f.attr("/volts_b", "units", "furlong");
  }
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " analyze --stats oadev -o " +
                                  (dir / "out").string() + " " + (dir / "u.h5").string(),
                              &out),
            0)
      << out;
  // One warning for the file's unknown unit, naming its channels (none under -q, which
  // prints errors only: tests/cli/test_progress.cpp).
  EXPECT_NE(out.find("unit 'furlong' (/volts_a, /volts_b) is not in allanlot's vocabulary"),
            std::string::npos)
      << out;
  std::size_t warnings = 0;
  for (std::size_t at = out.find("warning:"); at != std::string::npos;
       at = out.find("warning:", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << out;
  const auto r = io::read_results(dir / "out" / "u.allan.h5");
  EXPECT_EQ(channel(r, "/gyro_dps").units, "deg/s");
  EXPECT_EQ(channel(r, "/accel_ms2").units, "m/s^2");
  EXPECT_EQ(channel(r, "/clock_ppb").units, "1");
  EXPECT_EQ(channel(r, "/volts_a").units, "furlong");
  // The ppb channel is the same samples scaled by 1e-9: its deviations are 1e-9 of the
  // dimensionless channel's, to rounding (one product per sample).
  const auto& one = channel(r, "/clock_1").stats.at(0).second;
  const auto& ppb = channel(r, "/clock_ppb").stats.at(0).second;
  ASSERT_EQ(one.dev.size(), ppb.dev.size());
  for (std::size_t i = 0; i < one.dev.size(); ++i)
    EXPECT_NEAR(ppb.dev[i] / (1e-9 * one.dev[i]), 1.0, 1e-12) << i;
  // The gyro's coefficients have datasheet forms (deg/h ...), the unknown unit's do not.
  ASSERT_TRUE(channel(r, "/gyro_dps").fit.has_value());
  EXPECT_EQ(channel(r, "/gyro_dps").fit->terms[2].unit_datasheet, "deg/h");
}

// A CSV log's header units go through the same vocabulary as HDF5 attributes.
TEST(UnitsVocabulary, CsvHeaderUnitsAreReadAsTheCanonicalUnits) {
  const auto dir = test::fresh_dir("units_vocabulary_csv");
  const auto y = white(5000, 4);
  {
    std::ofstream csv(dir / "log.csv");
    csv << "time,gyro [dps],clock [ppb]\n";
    for (std::size_t i = 0; i < y.size(); ++i)
      csv << 0.01 * static_cast<double>(i) << "," << y[i] << "," << y[i] << "\n";
  }
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " analyze -q --stats oadev -o " +
                                  (dir / "out").string() + " " + (dir / "log.csv").string(),
                              &out),
            0)
      << out;
  const auto r = io::read_results(dir / "out" / "log.allan.h5");
  EXPECT_EQ(channel(r, "/gyro").units, "deg/s");
  EXPECT_EQ(channel(r, "/clock").units, "1");
  const auto& g = channel(r, "/gyro").stats.at(0).second;
  const auto& c = channel(r, "/clock").stats.at(0).second;
  ASSERT_EQ(g.dev.size(), c.dev.size());
  for (std::size_t i = 0; i < g.dev.size(); ++i)
    EXPECT_NEAR(c.dev[i] / (1e-9 * g.dev[i]), 1.0, 1e-12) << i;
}

}  // namespace
}  // namespace allanlot
