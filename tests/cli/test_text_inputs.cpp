// Text recordings through the real binary: PHASE.DAT (plain and gzipped) against Stable32's
// tables, a CSV with a time column and dropped rows, usage errors for what a file cannot say,
// a corrupt line, manifests named with @, `convert` then `analyze` bit for bit, the data
// type of HDF5 channels (default, --data-type), a folder of rig CSV files as a lot with
// channel globs, and --units per column.
#include "io/recording.hpp"
#include "io/results.hpp"
#include "reference/stable32.hpp"
#include "support/h5_fixture.hpp"
#include "support/text_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

const io::ChannelResult& channel(const io::RecordingResult& r, const std::string& path) {
  for (const auto& c : r.channels)
    if (c.path == path) return c;
  throw std::runtime_error("no channel " + path);
}

// A string attribute of a results file's root (read_results keeps only the schema's), "" when
// absent.
std::string root_attribute(const fs::path& file, const std::string& name) {
  std::string value;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return value;
  if (H5Aexists_by_name(f, "/", name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t a = H5Aopen_by_name(f, "/", name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    char* s = nullptr;
    if (H5Tis_variable_str(t) > 0 && H5Aread(a, t, &s) >= 0 && s) {
      value = s;
      H5free_memory(s);
    }
    H5Tclose(t);
    H5Aclose(a);
  }
  H5Fclose(f);
  return value;
}

const kernels::StatResult& stat(const io::ChannelResult& c, const std::string& name) {
  for (const auto& [n, s] : c.stats)
    if (n == name) return s;
  throw std::runtime_error("no statistic " + name);
}

// Stable32 prints 5 significant digits (as tests/kernels/test_allan_oadev.cpp).
constexpr double kStable32Rel = 1e-4;

TEST(TextInputs, PhaseDatPlainAndGzippedMatchStable32) {
  const fs::path dir = test::fresh_dir("text_cli_phasedat");
  const fs::path plain = test::reference_path("stable32/phasedat/PHASE.DAT");
  fs::create_directories(dir / "gz");
  ASSERT_TRUE(test::gzip_copy(plain, dir / "gz" / "PHASE.DAT.gz"));
  for (const fs::path& input : {plain, dir / "gz" / "PHASE.DAT.gz"}) {
    const fs::path out = dir / ("out_" + input.extension().string().substr(1));
    std::string text;
    ASSERT_EQ(run_command(binary() +
                              " analyze -q --data-type phase --sample-rate 1 --taus octave "
                              "--stats oadev,mdev,tdev,hdev,ohdev,totdev -o " +
                              out.string() + " " + input.string(),
                          &text),
              0)
        << text;
    const auto r = io::read_results(out / "PHASE.allan.h5");
    const io::ChannelResult& ch = channel(r, "/data");
    EXPECT_EQ(ch.data_type, "phase");
    EXPECT_EQ(ch.n_samples, 1001);
    for (const char* name : {"oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"}) {
      const auto rows =
          test::read_stable32("stable32/phasedat/phase_dat_" + std::string(name) + "_octave.txt");
      const kernels::StatResult& s = stat(ch, name);
      ASSERT_FALSE(rows.empty()) << name;
      std::size_t matched = 0;
      for (const auto& row : rows)
        for (std::size_t i = 0; i < s.size(); ++i)
          if (s.m[i] == row.m) {
            EXPECT_NEAR(s.dev[i] / row.sigma, 1.0, kStable32Rel) << name << " m=" << row.m;
            ++matched;
          }
      EXPECT_EQ(matched, rows.size()) << name << " " << input;
    }
  }
}

TEST(TextInputs, CsvWithMsTimeColumnCountsDroppedRowsAsGaps) {
  const fs::path dir = test::fresh_dir("text_cli_csv");
  test::write_imu_csv(dir / "unit7.csv");
  std::string text;
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev -o " + (dir / "out").string() + " " +
                            (dir / "unit7.csv").string(),
                        &text),
            0)
      << text;
  const auto r = io::read_results(dir / "out" / "unit7.allan.h5");
  ASSERT_EQ(r.channels.size(), 6u);
  for (const auto& ch : r.channels) {
    EXPECT_EQ(ch.n_gaps, 137) << ch.path;
    EXPECT_NEAR(ch.sample_rate_hz / 400.0, 1.0, 1e-9) << ch.path;
    EXPECT_EQ(ch.data_type, "rate (default)") << ch.path;
  }
  EXPECT_EQ(channel(r, "/gy").units, "deg/s");
  EXPECT_EQ(channel(r, "/az").units, "m/s^2");
  const fs::path results = dir / "out" / "unit7.allan.h5";
  EXPECT_EQ(root_attribute(results, "time_column"), "timestamp");
  EXPECT_EQ(root_attribute(results, "time_unit"), "ms (header)");
  EXPECT_EQ(root_attribute(results, "time_missing_samples"), "137");
}

TEST(TextInputs, WhatAFileCannotSayIsAUsageError) {
  const fs::path dir = test::fresh_dir("text_cli_usage");
  std::ofstream(dir / "x.txt") << "# fractional frequency\n1e-12\n2e-12\n3e-12\n";
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q --sample-rate 1 -o " + (dir / "out").string() +
                            " " + (dir / "x.txt").string(),
                        &text),
            2);
  EXPECT_NE(text.find("usage error"), std::string::npos) << text;
  EXPECT_NE(text.find("--data-type"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(dir / "out" / "x.allan.h5"));
  EXPECT_EQ(run_command(binary() + " analyze -q --data-type rate -o " + (dir / "out").string() +
                            " " + (dir / "x.txt").string(),
                        &text),
            2);
  EXPECT_NE(text.find("--sample-rate"), std::string::npos) << text;
  EXPECT_EQ(run_command(binary() + " convert -q -o " + (dir / "conv").string() + " " +
                            (dir / "x.txt").string(),
                        &text),
            2);
  EXPECT_NE(text.find("--data-type"), std::string::npos) << text;
}

TEST(TextInputs, ACorruptLineIsNamed) {
  const fs::path dir = test::fresh_dir("text_cli_corrupt");
  std::ofstream(dir / "c.csv") << "time,x [V],y [V]\n0,1,2\n1,1,2\n2,1.x,2\n3,1,2\n";
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q -o " + (dir / "out").string() + " " +
                            (dir / "c.csv").string(),
                        &text),
            2);
  EXPECT_NE(text.find((dir / "c.csv").string() + ":line 4, column 2 (x): '1.x' is not a number"),
            std::string::npos)
      << text;
}

TEST(TextInputs, ManifestsAreNamedNotGuessed) {
  const fs::path dir = test::fresh_dir("text_cli_manifest");
  test::CsvSpec spec;
  spec.rows = 5000;
  spec.dropped = 0;
  test::write_imu_csv(dir / "a.csv", spec);
  std::ofstream(dir / "lot.txt") << "# the lot\na.csv\n";
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q --stats oadev -o " + (dir / "out").string() + " " +
                            (dir / "lot.txt").string(),
                        &text),
            2);
  EXPECT_NE(text.find("@" + (dir / "lot.txt").string()), std::string::npos) << text;
  EXPECT_EQ(run_command(binary() + " analyze -q --stats oadev -o " + (dir / "out").string() +
                            " --manifest " + (dir / "lot.txt").string(),
                        &text),
            0)
      << text;
  EXPECT_TRUE(fs::exists(dir / "out" / "a.allan.h5"));
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

TEST(TextInputs, ConvertThenAnalyseEqualsDirectAnalysisBitForBit) {
  const fs::path dir = test::fresh_dir("text_cli_convert");
  test::CsvSpec spec;
  spec.rows = 30000;
  test::write_imu_csv(dir / "unit7.csv", spec);
  ASSERT_TRUE(test::gzip_copy(dir / "unit7.csv", dir / "unit7.csv.gz"));
  fs::remove(dir / "unit7.csv");
  std::string text;
  ASSERT_EQ(run_command(binary() + " convert -q -o " + (dir / "conv").string() + " " +
                            (dir / "unit7.csv.gz").string(),
                        &text),
            0)
      << text;
  ASSERT_TRUE(fs::exists(dir / "conv" / "unit7.h5"));
  for (const auto& [input, out] : {std::pair{dir / "unit7.csv.gz", dir / "direct"},
                                   std::pair{dir / "conv" / "unit7.h5", dir / "converted"}})
    ASSERT_EQ(
        run_command(binary() + " analyze -q -o " + out.string() + " " + input.string(), &text), 0)
        << text;
  const auto a = io::read_results(dir / "direct" / "unit7.allan.h5");
  const auto b = io::read_results(dir / "converted" / "unit7.allan.h5");
  EXPECT_EQ(a.device_id, b.device_id);
  for (const char* key : {"input_hash", "time_column", "time_unit", "time_missing_samples",
                          "time_step_s", "time_jitter_rms_s", "source_file_name"}) {
    const std::string va = root_attribute(dir / "direct" / "unit7.allan.h5", key);
    EXPECT_FALSE(va.empty()) << key;
    EXPECT_EQ(va, root_attribute(dir / "converted" / "unit7.allan.h5", key)) << key;
  }
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (std::size_t c = 0; c < a.channels.size(); ++c) {
    const auto &x = a.channels[c], &y = b.channels[c];
    EXPECT_EQ(x.path, y.path);
    EXPECT_EQ(x.units, y.units);
    EXPECT_EQ(x.data_type, y.data_type);
    EXPECT_EQ(x.n_gaps, y.n_gaps);
    EXPECT_EQ(std::memcmp(&x.sample_rate_hz, &y.sample_rate_hz, sizeof(double)), 0);
    ASSERT_EQ(x.stats.size(), y.stats.size());
    for (std::size_t s = 0; s < x.stats.size(); ++s) {
      EXPECT_TRUE(same_bits(x.stats[s].second.dev, y.stats[s].second.dev)) << x.path;
      EXPECT_TRUE(same_bits(x.stats[s].second.dev_lo, y.stats[s].second.dev_lo)) << x.path;
      EXPECT_TRUE(same_bits(x.stats[s].second.dev_hi, y.stats[s].second.dev_hi)) << x.path;
    }
    ASSERT_TRUE(x.fit && y.fit);
    ASSERT_EQ(x.fit->terms.size(), y.fit->terms.size());
    for (std::size_t t = 0; t < x.fit->terms.size(); ++t)
      EXPECT_EQ(std::memcmp(&x.fit->terms[t].value, &y.fit->terms[t].value, sizeof(double)), 0);
  }
}

// convert: an HDF5 input (scale applied, data type kept), a second input with the same
// device id, an output that would replace its input, and --tau0 for a single column.
TEST(TextInputs, ConvertKeepsInputsAndDeviceIdsApart) {
  const fs::path dir = test::fresh_dir("text_cli_convert_rules");
  {
    test::H5Fixture f(dir / "u.h5");
    f.dataset("/clock/x", std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8}, H5T_STD_I16LE);
    f.attr("/clock", "sample_rate_hz", 2.0);
    f.attr("/clock", "scale", 0.5);
    f.attr("/clock", "data_type", "phase");
    f.attr("/", "device_id", "clock-1");
  }
  std::ofstream(dir / "clock-1.txt") << "1\n2\n3\n4\n";
  const auto before = test::snapshot(dir);
  std::string text;
  EXPECT_EQ(run_command(binary() + " convert -o " + (dir / "out").string() +
                            " --data-type phase --tau0 0.5 " + (dir / "u.h5").string() + " " +
                            (dir / "clock-1.txt").string(),
                        &text),
            1)
      << text;
  EXPECT_NE(text.find("device_id 'clock-1' is also that of"), std::string::npos) << text;
  ASSERT_TRUE(fs::exists(dir / "out" / "clock-1.h5"));
  const auto r = io::RecordingReader((dir / "out" / "clock-1.h5").string());
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_EQ(r.info().channels[0].path, "/clock/x");
  EXPECT_EQ(r.info().channels[0].data_type, kernels::DataType::Phase);
  EXPECT_EQ(r.info().channels[0].sample_rate_hz, 2.0);
  EXPECT_EQ(test::as_vector(r.read(r.info().channels[0])),
            (std::vector<double>{0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4}));
  fs::remove_all(dir / "out");
  EXPECT_TRUE(test::snapshot(dir) == before) << "an input changed";
  // A recording named by its device id, converted into its own directory: the output would be
  // the input, and is refused.
  fs::create_directories(dir / "same");
  fs::copy_file(dir / "u.h5", dir / "same" / "clock-1.h5");
  const std::string bytes = test::file_bytes(dir / "same" / "clock-1.h5");
  EXPECT_EQ(run_command(binary() + " convert -o " + (dir / "same").string() + " " +
                            (dir / "same" / "clock-1.h5").string(),
                        &text),
            2)
      << text;
  EXPECT_NE(text.find("input"), std::string::npos) << text;
  EXPECT_TRUE(test::file_bytes(dir / "same" / "clock-1.h5") == bytes);
}

TEST(TextInputs, DiagnoseNeedsTheSameOptions) {
  const fs::path dir = test::fresh_dir("text_cli_diagnose");
  std::ofstream(dir / "x.dat") << "1\n2\n3\n";
  std::string text;
  std::ofstream(dir / "m.json")
      << R"({"units": "deg/s", "sample_rate_hz": 1, "terms": {"N": 0.01}})";
  EXPECT_EQ(run_command(binary() + " diagnose --model " + (dir / "m.json").string() + " " +
                            (dir / "x.dat").string(),
                        &text),
            2);
  EXPECT_NE(text.find("--data-type"), std::string::npos) << text;
}

TEST(TextInputs, HdfDataTypeDefaultIsSaidAndTheOptionOverrides) {
  const fs::path dir = test::fresh_dir("text_cli_hdf_type");
  {
    test::H5Fixture f(dir / "u.h5");
    std::vector<double> v(4000);
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = std::sin(0.37 * static_cast<double>(i * i % 101));
    f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
    f.dataset("/imu/timestamp", v, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  // The data type is read with the channel and written before any fit; this record fits
  // eq. (3) poorly, and modelling it as diagnose does (test_channel_model.cpp) would take 20
  // times the run under ASan without touching the data type.
  const std::string analyze = binary() + " analyze --model-poor-fits off --stats oadev ";
  std::string text;
  ASSERT_EQ(
      run_command(analyze + "-q -o " + (dir / "a").string() + " " + (dir / "u.h5").string(), &text),
      0)
      << text;
  const auto a = io::read_results(dir / "a" / "u.allan.h5");
  ASSERT_EQ(a.channels.size(), 1u);
  EXPECT_EQ(a.channels[0].data_type, "rate (default)");
  // The terminal table and the report say it too.
  ASSERT_EQ(run_command(analyze + "--force -o " + (dir / "a").string() + " " +
                            (dir / "u.h5").string() + " 2>/dev/null",
                        &text),
            0)
      << text;
  EXPECT_NE(text.find("data type rate (default) for gyro_x"), std::string::npos) << text;
  ASSERT_EQ(run_command(binary() + " report -q --unit-pages always -o " +
                            (dir / "r.html").string() + " " + (dir / "a").string(),
                        &text),
            0)
      << text;
  bool said = false;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".html")
      said = said || test::file_bytes(e.path()).find("rate (default)") != std::string::npos;
  EXPECT_TRUE(said);
  ASSERT_EQ(run_command(analyze + "-q --data-type phase -o " + (dir / "b").string() + " " +
                            (dir / "u.h5").string(),
                        &text),
            0)
      << text;
  EXPECT_EQ(io::read_results(dir / "b" / "u.allan.h5").channels[0].data_type, "phase");
}

// A CSV log whose clock repeats two records and steps back once: analysed whole, and the
// quality screen names it in the lot summary (docs/quality.md "time stamps").
TEST(TextInputs, TimeStampsOutOfOrderReachTheQualityScreen) {
  const fs::path dir = test::fresh_dir("text_time_quality");
  test::CsvSpec spec;
  spec.rows = 4000;
  spec.dropped = 0;
  test::write_imu_csv(dir / "c.csv", spec);
  std::vector<std::string> lines = test::read_lines(dir / "c.csv");
  lines.insert(lines.begin() + 1001, lines[1000]);  // a record written twice
  lines.insert(lines.begin() + 2001, lines[2000]);
  lines[3000] = lines[10];  // a stamp set back
  test::write_lines(dir / "clock.csv", lines);
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " analyze -q --stats oadev -o " +
                                  (dir / "out").string() + " " + (dir / "clock.csv").string(),
                              &out),
            0)
      << out;
  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& r : rows) {
    EXPECT_EQ(r.n_time_errors, 3) << r.channel;
    EXPECT_NE(r.quality.find("time_stamps"), std::string::npos) << r.channel << " " << r.quality;
    EXPECT_EQ(r.n_samples, 4002) << r.channel;
  }
}

// A rig's lot as it is handed over: a folder of .csv, .csv.gz and .tsv recordings (epoch-ns
// stamps with jitter, units in the header, a temperature column, dropped rows) beside a
// README, analysed with --channels globs: every unit at 100 Hz to 1e-9, the gyroscopes and
// accelerometers with their header units, never the temperature; -q prints nothing.
TEST(TextInputs, AFolderOfRigCsvFilesIsALotAndChannelGlobsSelect) {
  const fs::path dir = test::fresh_dir("text_cli_rig_lot");
  const fs::path lot = dir / "lot";
  fs::create_directories(lot);
  // 1e5 rows: the fitted step's error is 20 us * sqrt(12 / N^3) / 10 ms = 2.2e-10 (1e-9 is 4.5
  // of it); at 3e4 rows it would be 1.3e-9.
  test::RigSpec spec;
  test::write_rig_csv(dir / "rig1.csv", spec);
  ASSERT_TRUE(test::gzip_copy(dir / "rig1.csv", lot / "rig1.csv.gz"));
  spec.seed = 12;
  test::write_rig_csv(lot / "rig2.csv", spec);
  spec.seed = 13;
  spec.sep = '\t';
  test::write_rig_csv(lot / "rig3.tsv", spec);
  std::ofstream(lot / "README.txt") << "rig 4, bench 2\n";
  const auto run = [&](const std::string& options, const std::string& out, std::string& text) {
    return run_command(binary() + " analyze -q --stats oadev --no-psd -o " + (dir / out).string() +
                           " " + options + " " + lot.string(),
                       &text);
  };
  std::string text;
  ASSERT_EQ(run("--channels 'gyro_*,accel_*'", "out", text), 0) << text;
  EXPECT_EQ(text, "") << "-q prints errors only";
  for (const char* unit : {"rig1", "rig2", "rig3"}) {
    const auto r = io::read_results(dir / "out" / (std::string(unit) + ".allan.h5"));
    std::vector<std::string> paths;
    for (const auto& ch : r.channels) {
      paths.push_back(ch.path);
      EXPECT_NEAR(ch.sample_rate_hz / 100.0, 1.0, 1e-9) << unit << ch.path;
      EXPECT_EQ(ch.n_gaps, 12) << unit << ch.path;
      EXPECT_EQ(ch.units, ch.path[1] == 'g' ? "deg/s" : "g") << unit << ch.path;
    }
    EXPECT_EQ(paths, (std::vector<std::string>{"/accel_x", "/accel_z", "/gyro_x", "/gyro_y"}))
        << unit;
  }
  // The same selection by excluding: --exclude-channels, or '!' among --channels (only the
  // channel list is checked, so without the fit, which is most of the run under ASan).
  for (const std::string& options : {std::string("--no-fit --exclude-channels 'temp*'"),
                                     std::string("--no-fit --channels '!temp' --channels '*'")}) {
    ASSERT_EQ(run(options, "out_excluded", text), 0) << options << "\n" << text;
    const auto r = io::read_results(dir / "out_excluded" / "rig2.allan.h5");
    EXPECT_EQ(r.channels.size(), 4u) << options;
    for (const auto& ch : r.channels)
      EXPECT_NE(ch.path, "/temp") << options;
  }
}

// A folder without recordings names what was looked for; a selection that matches no channel
// of a recording fails it, naming the recording, the selection and its channels; an include
// glob that matches nothing while others match is a note.
TEST(TextInputs, AFolderWithoutRecordingsAndASelectionWithoutChannelsAreNamed) {
  const fs::path dir = test::fresh_dir("text_cli_rig_none");
  fs::create_directories(dir / "notes");
  std::ofstream(dir / "notes" / "README.txt") << "nothing here\n";
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -o " + (dir / "out").string() + " " +
                            (dir / "notes").string(),
                        &text),
            2);
  EXPECT_NE(text.find("directory contains no recording (looked for *.h5, *.hdf5, *.csv, *.tsv, "
                      "*.csv.gz, *.tsv.gz"),
            std::string::npos)
      << text;
  test::RigSpec spec;
  spec.rows = 5000;
  test::write_rig_csv(dir / "rig.csv", spec);
  const std::string file = (dir / "rig.csv").string();
  EXPECT_EQ(run_command(binary() + " analyze -q --stats oadev --no-psd --channels 'mag_*' -o " +
                            (dir / "out").string() + " " + file,
                        &text),
            2);
  EXPECT_NE(text.find(file + ": no channel matches --channels 'mag_*' "
                             "(its channels: /accel_x, /accel_z, /gyro_x, /gyro_y, /temp)"),
            std::string::npos)
      << text;
  EXPECT_EQ(run_command(binary() + " analyze --stats oadev --no-psd --channels 'gyro_*,mag_*' -o " +
                            (dir / "out").string() + " " + file,
                        &text),
            0);
  EXPECT_NE(text.find(file + ": --channels 'mag_*' matches no channel of this recording"),
            std::string::npos)
      << text;
}

// --units per column glob (over the header) and bare (for the columns that name none), each
// unit validated against the vocabulary: a misspelt one is a usage error naming the option.
TEST(TextInputs, UnitsPerColumnGlob) {
  const fs::path dir = test::fresh_dir("text_cli_units");
  test::RigSpec spec;
  spec.rows = 5000;
  test::write_rig_csv(dir / "rig.csv", spec);
  std::vector<std::string> lines = test::read_lines(dir / "rig.csv");
  lines[0] = "timestamp_ns,gyro_x,gyro_y,accel_x,accel_z,temp [degC]";
  test::write_lines(dir / "bare.csv", lines);
  std::string text;
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev --no-psd --no-fit " +
                            "--units 'gyro_*=deg/h' --units 'accel_*=mg' -o " +
                            (dir / "out").string() + " " + (dir / "bare.csv").string(),
                        &text),
            0)
      << text;
  const auto r = io::read_results(dir / "out" / "bare.allan.h5");
  EXPECT_EQ(channel(r, "/gyro_y").units, "deg/h");
  EXPECT_EQ(channel(r, "/accel_x").units, "mg");
  EXPECT_EQ(channel(r, "/temp").units, "degC");
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev --no-psd --no-fit --units g -o " +
                            (dir / "out2").string() + " " + (dir / "rig.csv").string(),
                        &text),
            0)
      << text;
  const auto h = io::read_results(dir / "out2" / "rig.allan.h5");
  EXPECT_EQ(channel(h, "/gyro_x").units, "deg/s") << "the header's unit over a bare --units";
  EXPECT_EQ(run_command(binary() + " analyze -q --units 'gyro_*=deg/sex' -o " +
                            (dir / "out3").string() + " " + (dir / "bare.csv").string(),
                        &text),
            2);
  EXPECT_NE(text.find("--units"), std::string::npos) << text;
  EXPECT_NE(text.find("'deg/sex' is not a unit allanlot knows (for the columns 'gyro_*')"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace allanlot
