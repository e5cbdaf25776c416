// Text recordings through io::RecordingReader: single-column files (PHASE.DAT, plain and
// gzipped), CSV with a time column, gaps and jitter, malformed lines, usage errors, and the
// names that are never channels in HDF5 files.
#include "io/error.hpp"
#include "io/recording.hpp"
#include "io/text_fields.hpp"
#include "io/text_recording.hpp"
#include "io/usage_error.hpp"
#include "reference/stable32.hpp"
#include "support/h5_fixture.hpp"
#include "support/text_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

io::InputOptions phase_at(double rate) {
  io::InputOptions o;
  o.data_type = kernels::DataType::Phase;
  o.sample_rate_hz = rate;
  return o;
}

std::int64_t count_nan(const std::vector<double>& v) {
  std::int64_t n = 0;
  for (const double x : v)
    n += std::isnan(x) ? 1 : 0;
  return n;
}

// The error's message, or "" when `f` does not throw E.
template <class E, class F>
std::string message_of(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

TEST(TextRecording, PhaseDatPlainAndGzippedReadAsTheReference) {
  const fs::path dir = test::fresh_dir("text_phasedat");
  const fs::path plain = test::reference_path("stable32/phasedat/PHASE.DAT");
  ASSERT_TRUE(test::gzip_copy(plain, dir / "PHASE.DAT.gz"));
  const auto expected = test::read_column("stable32/phasedat/PHASE.DAT");
  for (const fs::path& p : {plain, dir / "PHASE.DAT.gz"}) {
    const io::RecordingReader r(p.string(), phase_at(1.0));
    EXPECT_EQ(r.info().device_id, "PHASE");
    ASSERT_EQ(r.info().channels.size(), 1u);
    const io::ChannelInfo& ch = r.info().channels[0];
    EXPECT_EQ(ch.path, "/data");
    EXPECT_EQ(ch.data_type, kernels::DataType::Phase);
    EXPECT_FALSE(ch.data_type_default);
    EXPECT_EQ(ch.sample_rate_hz, 1.0);
    EXPECT_EQ(test::as_vector(r.read(ch)), expected) << p;
  }
}

TEST(TextRecording, SingleColumnNeedsDataTypeRateAndColumn) {
  const fs::path dir = test::fresh_dir("text_usage");
  std::ofstream(dir / "x.dat") << "% a comment\n; another\n1.5\n2.5\n3.5\n";
  std::ofstream(dir / "tagged.txt") << "59000.0 1e-9\n59000.1 2e-9\n59000.2 3e-9\n";
  std::ofstream(dir / "three.txt") << "1 2 3\n4 5 6\n";
  const auto usage = [](const fs::path& p, const io::InputOptions& o) {
    return message_of<io::UsageError>([&] { io::RecordingReader r(p.string(), o); });
  };
  io::InputOptions none;
  EXPECT_NE(usage(dir / "x.dat", none).find("--data-type rate|phase"), std::string::npos);
  none.data_type = kernels::DataType::Rate;
  EXPECT_NE(usage(dir / "x.dat", none).find("--sample-rate"), std::string::npos);
  EXPECT_NE(usage(dir / "three.txt", phase_at(1)).find("--column"), std::string::npos);
  EXPECT_THROW(io::check_input_options((dir / "x.dat").string(), {}), io::UsageError);

  const io::RecordingReader tagged((dir / "tagged.txt").string(), phase_at(10));
  EXPECT_EQ(test::as_vector(tagged.read(tagged.info().channels[0])),
            (std::vector<double>{1e-9, 2e-9, 3e-9}));
  io::InputOptions first = phase_at(1);
  first.column = 1;
  const io::RecordingReader three((dir / "three.txt").string(), first);
  EXPECT_EQ(test::as_vector(three.read(three.info().channels[0])), (std::vector<double>{1, 4}));
}

TEST(TextRecording, CsvTimeColumnInMsGivesRateUnitsAndGaps) {
  const fs::path dir = test::fresh_dir("text_csv");
  test::write_imu_csv(dir / "unit7.csv");
  ASSERT_TRUE(test::gzip_copy(dir / "unit7.csv", dir / "unit7.csv.gz"));
  for (const char* name : {"unit7.csv", "unit7.csv.gz"}) {
    const io::RecordingReader r((dir / name).string());
    EXPECT_EQ(r.info().device_id, "unit7");
    ASSERT_EQ(r.info().channels.size(), 6u) << "the time column is never a channel";
    for (const io::ChannelInfo& ch : r.info().channels) {
      EXPECT_NEAR(ch.sample_rate_hz / 400.0, 1.0, 1e-9) << ch.path;
      EXPECT_EQ(ch.n_samples, 20000) << ch.path;
      EXPECT_TRUE(ch.data_type_default);
      EXPECT_EQ(ch.units, ch.path[1] == 'g' ? "deg/s" : "m/s^2") << ch.path;
      EXPECT_EQ(count_nan(test::as_vector(r.read(ch))), 137) << ch.path;
    }
    EXPECT_EQ(r.info().channels[0].path, "/ax");
    bool facts = false;
    for (const auto& [k, v] : r.info().facts)
      facts = facts || (k == "time_missing_samples" && v == "137");
    EXPECT_TRUE(facts);
  }
}

TEST(TextRecording, JitterIsANoteAndIsoTimesAreRead) {
  const fs::path dir = test::fresh_dir("text_jitter");
  test::CsvSpec spec;
  spec.rows = 2000;
  spec.dropped = 0;
  spec.jitter_ms = 0.1;  // 4 % of the 2.5 ms step
  test::write_imu_csv(dir / "j.csv", spec);
  const io::RecordingReader j((dir / "j.csv").string());
  ASSERT_EQ(j.info().notes.size(), 1u);
  EXPECT_NE(j.info().notes[0].find("timing jitter"), std::string::npos) << j.info().notes[0];

  // Across midnight, with a missing sample before the last.
  std::ofstream(dir / "iso.tsv") << "time\tx (V)\n2024-05-01T23:59:59.5Z\t1\n"
                                 << "2024-05-02T00:00:00.0Z\t2\n2024-05-02T00:00:00.5Z\t3\n"
                                 << "2024-05-02T00:00:01.5Z\t4\n";
  const io::RecordingReader iso((dir / "iso.tsv").string());
  ASSERT_EQ(iso.info().channels.size(), 1u);
  EXPECT_EQ(iso.info().channels[0].sample_rate_hz, 2.0);
  EXPECT_EQ(iso.info().channels[0].units, "V");
  const auto x = iso.read(iso.info().channels[0]);
  ASSERT_EQ(x.size(), 5u);
  EXPECT_TRUE(std::isnan(x[3]));
  EXPECT_EQ(x[4], 4.0);
}

TEST(TextRecording, MalformedLinesNameFileLineAndColumn) {
  const fs::path dir = test::fresh_dir("text_corrupt");
  test::CsvSpec spec;
  spec.rows = 100;
  spec.dropped = 0;
  test::write_imu_csv(dir / "c.csv", spec);
  const std::vector<std::string> lines = test::read_lines(dir / "c.csv");
  const auto write_with = [&](const std::string& name, std::size_t at, const std::string& line) {
    std::vector<std::string> copy = lines;
    copy[at - 1] = line;
    test::write_lines(dir / name, copy);
    return (dir / name).string();
  };
  const std::string bad_value = write_with("v.csv", 57, "1700000000137.500,1,2,x3,4,5,6");
  const std::string e1 =
      message_of<io::Error>([&] { io::RecordingReader r(bad_value, io::InputOptions{}); });
  EXPECT_NE(e1.find(bad_value + ":line 57, column 4 (gz): 'x3' is not a number"), std::string::npos)
      << e1;
  const std::string short_line = write_with("s.csv", 80, "1700000000197.500,1,2,3,4,5");
  const std::string e2 =
      message_of<io::Error>([&] { io::RecordingReader r(short_line, io::InputOptions{}); });
  EXPECT_NE(e2.find("line 80: has 6 field(s), the header (line 1) has 7"), std::string::npos) << e2;
}

// Time stamps repeated or out of order (a logger's clock stepping back) are not refused: each is
// the next sample, counted for the data-quality screen (docs/quality.md), and makes no gap.
TEST(TextRecording, RepeatedAndDecreasingTimeStampsAreCounted) {
  const fs::path dir = test::fresh_dir("text_time_order");
  test::CsvSpec spec;
  spec.rows = 100;
  spec.dropped = 0;
  test::write_imu_csv(dir / "c.csv", spec);
  std::vector<std::string> lines = test::read_lines(dir / "c.csv");
  // Line 30 (row 29) goes back to the first stamp; lines 41 and 61 repeat their predecessor's.
  lines[29] = "1700000000000.000,1,2,3,4,5,6";
  for (const std::size_t at : {40u, 60u})
    lines[at] = lines[at - 1];
  test::write_lines(dir / "b.csv", lines);
  io::RecordingReader r((dir / "b.csv").string(), io::InputOptions{});
  ASSERT_FALSE(r.info().channels.empty());
  const io::ChannelInfo& ch = r.info().channels[0];
  EXPECT_EQ(ch.n_samples, 100);  // every row a sample, no gap after the stamp that went back
  EXPECT_EQ(ch.time_stamps.n_decreasing, 1);
  EXPECT_EQ(ch.time_stamps.first_decreasing, 28);
  EXPECT_EQ(ch.time_stamps.n_duplicate, 2);
  EXPECT_EQ(ch.time_stamps.first_duplicate, 39);
  ASSERT_EQ(r.info().notes.size(), 1u);
  EXPECT_NE(r.info().notes[0].find("2 repeated and 1 decreasing time stamp(s)"), std::string::npos)
      << r.info().notes[0];
}

// A gzip stream cut short is an error, never a shorter record.
TEST(TextRecording, TruncatedGzipIsAnError) {
  const fs::path dir = test::fresh_dir("text_gzip_cut");
  ASSERT_TRUE(test::gzip_copy(test::reference_path("stable32/phasedat/PHASE.DAT"), dir / "p.gz"));
  fs::resize_file(dir / "p.gz", fs::file_size(dir / "p.gz") / 2);
  const std::string e =
      message_of<io::Error>([&] { io::RecordingReader r((dir / "p.gz").string(), phase_at(1.0)); });
  EXPECT_NE(e.find("truncated or corrupt compressed data"), std::string::npos) << e;
}

std::string fact(const io::RecordingInfo& info, const std::string& key) {
  for (const auto& [k, v] : info.facts)
    if (k == key) return v;
  return "";
}

// A 100 Hz logger's epoch-ns stamps (1.76e18, beyond double's 2^53: read as doubles they step
// in 256 ns and the rate came out 99.99872 Hz) with 20 us rms jitter: read as integers and the
// step fitted over the sample numbers, the rate is 100 Hz to 1e-9 (the fit's error is about
// 20 us * sqrt(12 / N^3) / 10 ms = 2e-10 for N = 1e5, where the median step's is 1e-5); the
// dropped rows are the gaps, plain and gzipped.
TEST(TextRecording, EpochNanosecondStampsWithJitterGiveTheRateExactly) {
  const fs::path dir = test::fresh_dir("text_epoch_ns");
  test::write_rig_csv(dir / "rig.csv");
  ASSERT_TRUE(test::gzip_copy(dir / "rig.csv", dir / "rig7.csv.gz"));
  for (const char* name : {"rig.csv", "rig7.csv.gz"}) {
    const io::RecordingReader r((dir / name).string());
    ASSERT_EQ(r.info().channels.size(), 5u) << "timestamp_ns is the time column";
    for (const io::ChannelInfo& ch : r.info().channels) {
      EXPECT_NEAR(ch.sample_rate_hz / 100.0, 1.0, 1e-9) << ch.path;
      EXPECT_EQ(ch.n_samples, 100000) << ch.path;
      EXPECT_EQ(count_nan(test::as_vector(r.read(ch))), 12) << ch.path;
    }
    EXPECT_EQ(fact(r.info(), "time_column"), "timestamp_ns");
    EXPECT_EQ(fact(r.info(), "time_unit"), "ns (header)");
    EXPECT_EQ(fact(r.info(), "time_missing_samples"), "12");
    // The jitter as written (20 us rms of each stamp; a step's is sqrt(2) that).
    EXPECT_NEAR(std::stod(fact(r.info(), "time_jitter_rms_s")) / (std::sqrt(2.0) * 20e-6), 1.0,
                0.02);
  }
}

// The same stamps as decimal seconds with nine decimals keep their nanoseconds too.
TEST(TextRecording, DecimalEpochSecondsGiveTheRateExactly) {
  const fs::path dir = test::fresh_dir("text_epoch_s");
  test::write_rig_csv(dir / "ns.csv");
  std::vector<std::string> lines = test::read_lines(dir / "ns.csv");
  lines[0] = "time [s]" + lines[0].substr(12);
  for (std::size_t i = 1; i < lines.size(); ++i)
    lines[i] = lines[i].substr(0, 10) + "." + lines[i].substr(10);  // 1764300000.010001269
  test::write_lines(dir / "s.csv", lines);
  const io::RecordingReader r((dir / "s.csv").string());
  ASSERT_FALSE(r.info().channels.empty());
  EXPECT_NEAR(r.info().channels[0].sample_rate_hz / 100.0, 1.0, 1e-9);
  EXPECT_EQ(fact(r.info(), "time_missing_samples"), "12");
}

// A stamp beyond int64 is an error naming the file, the line and the column, never a
// rounded number; so is one whose distance from the first overflows.
TEST(TextRecording, StampBeyondInt64IsAnErrorNamingTheLine) {
  const fs::path dir = test::fresh_dir("text_stamp_range");
  test::RigSpec spec;
  spec.rows = 50;
  spec.dropped = 0;
  test::write_rig_csv(dir / "ok.csv", spec);
  std::vector<std::string> lines = test::read_lines(dir / "ok.csv");
  const std::string row = lines[9].substr(lines[9].find(','));
  lines[9] = "92233720368547758080" + row;  // ten times int64's largest
  test::write_lines(dir / "big.csv", lines);
  const std::string big = (dir / "big.csv").string();
  const std::string e = message_of<io::Error>([&] { io::RecordingReader r(big); });
  EXPECT_NE(e.find(big + ":line 10, column 1 (timestamp_ns): '92233720368547758080' is beyond "
                         "the range of a time stamp"),
            std::string::npos)
      << e;
  lines[9] = "-9000000000000000000" + row;
  test::write_lines(dir / "far.csv", lines);
  const std::string far = (dir / "far.csv").string();
  const std::string e2 = message_of<io::Error>([&] { io::RecordingReader r(far); });
  EXPECT_NE(e2.find(far + ":line 10, column 1 (timestamp_ns)"), std::string::npos) << e2;
  EXPECT_NE(e2.find("too far from the first time stamp"), std::string::npos) << e2;
}

// Units: the header's, in brackets or parentheses; --units GLOB=UNIT over the header for the
// columns it matches (with a note when they differ), a bare --units for the columns that name
// none.
TEST(TextRecording, UnitsFromTheHeaderAndFromUnitsGlobs) {
  const fs::path dir = test::fresh_dir("text_units");
  std::ofstream(dir / "u.csv") << "t_ms,gyro_x [rad/s],gyro_y,accel_x (g),temp [degC],v\n"
                               << "0,1,2,3,4,5\n10,1,2,3,4,5\n20,1,2,3,4,5\n";
  const auto units_of = [&](const io::InputOptions& o) {
    const io::RecordingReader r((dir / "u.csv").string(), o);
    std::map<std::string, std::string> u;
    for (const io::ChannelInfo& ch : r.info().channels)
      u[ch.path] = ch.units;
    return std::pair{u, r.info().notes};
  };
  const auto [header, no_notes] = units_of({});
  EXPECT_EQ(header, (std::map<std::string, std::string>{{"/accel_x", "g"},
                                                        {"/gyro_x", "rad/s"},
                                                        {"/gyro_y", ""},
                                                        {"/temp", "degC"},
                                                        {"/v", ""}}));
  EXPECT_TRUE(no_notes.empty());
  io::InputOptions o;
  o.units = {{"gyro_*", "dps"}, {"", "mg"}};
  const auto [given, notes] = units_of(o);
  EXPECT_EQ(given, (std::map<std::string, std::string>{{"/accel_x", "g"},
                                                       {"/gyro_x", "deg/s"},
                                                       {"/gyro_y", "deg/s"},
                                                       {"/temp", "degC"},
                                                       {"/v", "mg"}}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "column 'gyro_x': --units 'gyro_*=dps' replaces the header's unit 'rad/s'");
}

TEST(TextRecording, DeviceIdAndNames) {
  EXPECT_EQ(io::text_device_id("/a/unit7.csv.gz"), "unit7");
  EXPECT_EQ(io::text_device_id("PHASE.DAT"), "PHASE");
  EXPECT_EQ(io::text_device_id("run.2024.tsv"), "run.2024");
  EXPECT_TRUE(io::is_text_name("x.TXT.GZ"));
  EXPECT_FALSE(io::is_text_name("x.h5"));
  for (const char* name : {"timestamp_ns", "time_ms", "T_US", "stamp_s", "gps_time", "Time"})
    EXPECT_TRUE(io::is_time_name(name)) << name;
  for (const char* name : {"gyro_x", "temp_s", "_ns", "ns"})
    EXPECT_FALSE(io::is_time_name(name)) << name;
}

// HDF5: datasets named like time stamps are never channels; a channel without data_type is
// rate by default and says so; --data-type overrides the file.
TEST(TextRecording, HdfTimeNamesAndDataTypeDefaults) {
  const fs::path dir = test::fresh_dir("text_hdf_defaults");
  const fs::path file = dir / "u.h5";
  {
    test::H5Fixture f(file);
    const std::vector<double> v(100, 1.0);
    for (const char* name :
         {"/imu/gyro_x", "/imu/timestamp", "/imu/t", "/imu/gps_time", "/imu/stamp", "/clock/x"})
      f.dataset(name, v, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
    f.attr("/clock", "sample_rate_hz", 1.0);
    f.attr("/clock", "data_type", "phase");
  }
  const io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 2u);
  EXPECT_EQ(r.info().channels[0].path, "/clock/x");
  EXPECT_FALSE(r.info().channels[0].data_type_default);
  EXPECT_EQ(r.info().channels[1].path, "/imu/gyro_x");
  EXPECT_TRUE(r.info().channels[1].data_type_default);
  io::InputOptions rate;
  rate.data_type = kernels::DataType::Rate;
  const io::RecordingReader o(file.string(), rate);
  for (const io::ChannelInfo& ch : o.info().channels) {
    EXPECT_EQ(ch.data_type, kernels::DataType::Rate) << ch.path;
    EXPECT_FALSE(ch.data_type_default) << ch.path;
  }
}

}  // namespace
}  // namespace allanlot
