// The data-quality screen through the command line (docs/quality.md): a recording with an
// injected saturation and spikes gets its quality/ group, the lot summary's quality columns and
// the report's flags, a spec's "quality" limits fail it, and the spec's quality keys parse
// strictly.
#include "io/results.hpp"
#include "src/lot/spec.hpp"
#include "src/pipeline/channel_quality.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <random>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using spec::Outcome;
using test::binary;
using test::run_command;

spec::Spec parse(const std::string& text) {
  return spec::parse_spec(text, "spec.json");
}

std::string parse_error(const std::string& text) {
  try {
    parse(text);
  } catch (const spec::Error& e) {
    return e.what();
  }
  return "";
}

io::SummaryRow screened_row(std::int64_t spikes, std::int64_t saturated) {
  io::SummaryRow r{"SN1", "/imu/gyro_x", "deg/s", 1000, io::ChannelStatus::ok(), "/data/sn1.h5"};
  r.quality = spikes || saturated ? "saturation;spikes" : "ok";
  r.n_spikes = spikes;
  r.n_saturated = saturated;
  return r;
}

TEST(QualitySpec, ParsesLimitsAndFlags) {
  const spec::Spec s = parse(R"j({"channels": {"gyro_*": {"quality": {"max_spikes": 2,
      "saturation": "fail", "stuck": "ignore", "max_missing": 100}}}})j");
  ASSERT_TRUE(s.rules[0].quality);
  const spec::QualityLimits& q = *s.rules[0].quality;
  EXPECT_EQ(q.max_spikes, 2);
  EXPECT_EQ(q.max_saturated, 0);
  EXPECT_FALSE(q.max_stuck);
  EXPECT_EQ(q.max_missing, 100);
  EXPECT_FALSE(q.max_gaps);
  EXPECT_TRUE(s.rules[0].limits.empty());
}

TEST(QualitySpec, RefusesWhatItCannotRead) {
  EXPECT_EQ(parse_error(R"j({"channels": {"*": {"quality": {"max_spiks": 0}}}})j")
                .rfind("spec.json: channels.*.quality.max_spiks: unknown key", 0),
            0u);
  EXPECT_EQ(parse_error(R"j({"channels": {"*": {"quality": {"max_spikes": -1}}}})j"),
            "spec.json: channels.*.quality.max_spikes: must be an integer >= 0, got -1");
  EXPECT_EQ(parse_error(R"j({"channels": {"*": {"quality": {"max_spikes": 1.5}}}})j"),
            "spec.json: channels.*.quality.max_spikes: must be an integer >= 0, got 1.5");
  EXPECT_EQ(parse_error(R"j({"channels": {"*": {"quality": {"stuck": "yes"}}}})j"),
            "spec.json: channels.*.quality.stuck: must be \"fail\" or \"ignore\", got \"yes\"");
  EXPECT_EQ(
      parse_error(
          R"j({"channels": {"*": {"quality": {"saturation": "fail", "max_saturated": 3}}}})j"),
      "spec.json: channels.*.quality.max_saturated: give max_saturated or saturation, not both");
  EXPECT_EQ(parse_error(R"j({"channels": {"*": {"quality": {}}}})j"),
            "spec.json: channels.*.quality: must limit at least one quality count");
}

TEST(QualitySpec, ABadChannelFailsWhateverItsTerms) {
  const spec::Spec s = parse(R"j({"channels": {"gyro_*": {"quality": {"max_spikes": 0,
      "saturation": "fail"}, "N": {"max": 100, "unit": "deg/h/sqrt(Hz)"}}}})j");
  io::SummaryRow clean = screened_row(0, 0);
  clean.value[3] = 18;
  clean.sigma[3] = 0.1;
  clean.unit[3] = "deg/h/sqrt(Hz)";
  clean.detected[3] = 1;
  EXPECT_EQ(spec::judge(s, clean).status, "pass");
  io::SummaryRow bad = clean;
  bad.quality = "saturation;spikes";
  bad.n_spikes = 3;
  bad.n_saturated = 50;
  const spec::Verdict v = spec::judge(s, bad);
  EXPECT_EQ(v.status, "fail");
  EXPECT_EQ(v.detail, "quality: 3 spikes > 0; 50 saturated samples > 0");
  EXPECT_EQ(v.term_status[3], "pass");  // the term itself is within its limit
  // Without a fitted value (analyze --no-fit) bad data still fail.
  io::SummaryRow no_fit = screened_row(3, 0);
  EXPECT_EQ(spec::judge(s, no_fit).status, "fail");
  // A results file of an older version was not screened: a pass becomes undecided.
  io::SummaryRow old = clean;
  old.quality = "";
  EXPECT_EQ(spec::judge(s, old).status, "undecided");
  EXPECT_EQ(spec::judge(s, old).detail, "quality not screened");
  // A rule of quality alone decides a channel without a fitted value.
  const spec::Spec q_only = parse(R"j({"channels": {"*": {"quality": {"max_spikes": 0}}}})j");
  EXPECT_EQ(spec::judge(q_only, screened_row(0, 0)).status, "pass");
  EXPECT_EQ(spec::judge(q_only, screened_row(2, 0)).status, "fail");
  io::SummaryRow unscreened = screened_row(0, 0);
  unscreened.quality = "";
  EXPECT_EQ(spec::judge(q_only, unscreened).status, "undecided");
}

// A 16-bit gyro at 0.02 deg/s per count (noise of 8 counts) whose x axis is clipped at the
// type's limit for 50 samples (longer than the spike window, so not spikes themselves) and hit
// by three spikes; y is clean.
void write_recording(const fs::path& p) {
  test::H5Fixture f(p);
  std::mt19937_64 gen(5);
  std::normal_distribution<double> noise(0.0, 8.0);
  std::vector<double> x(60'000), y(60'000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = std::round(noise(gen));
    y[i] = std::round(noise(gen));
  }
  for (int i = 30'000; i < 30'050; ++i)
    x[i] = 32767;
  x[10'000] += 400;
  x[20'000] -= 500;
  x[40'000] += 900;
  f.dataset("/imu/gyro_x", x, H5T_STD_I16LE);
  f.dataset("/imu/gyro_y", y, H5T_STD_I16LE);
  f.attr("/imu", "sample_rate_hz", 100.0);
  f.attr("/imu", "scale", 0.02);
  f.attr("/imu/gyro_x", "units", "deg/s");
  f.attr("/imu/gyro_y", "units", "deg/s");
}

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  const auto split = [](const std::string& s) {
    std::vector<std::string> v;
    std::stringstream ss(s);
    std::string cell;
    while (std::getline(ss, cell, ','))
      v.push_back(cell);
    if (!s.empty() && s.back() == ',') v.emplace_back();
    return v;
  };
  std::getline(in, line);
  header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i)
      row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

TEST(QualityCommand, StorageLimitsInPhysicalUnits) {
  io::ChannelInfo ch;
  ch.storage_type = "int16";
  EXPECT_EQ(pipeline::storage_limits(ch), (std::pair{-32768.0, 32767.0}));
  ch.storage_type = "uint8";
  ch.scale = -0.5;  // a negative scale swaps the ends
  ch.offset = 10;
  EXPECT_EQ(pipeline::storage_limits(ch), (std::pair{10.0 - 127.5, 10.0}));
  ch.storage_type = "uint64";
  ch.scale = 1;
  ch.offset = 0;
  EXPECT_EQ(pipeline::storage_limits(ch), (std::pair{0.0, 18446744073709551615.0}));
  for (const char* t : {"float32", "float64", "int12", "string", ""}) {
    ch.storage_type = t;
    EXPECT_FALSE(pipeline::storage_limits(ch)) << t;
  }
}

TEST(QualityCommand, AnUnscreenedRowHasEmptyQualityColumns) {
  // A results file of an earlier version has no quality/ group: its counts must not read as a
  // clean 0 in the CSV.
  io::RecordingResult r;
  r.device_id = "SN0";
  io::ChannelResult ch;
  ch.path = "/imu/gyro_x";
  r.channels.push_back(ch);
  ch.path = "/imu/gyro_y";
  ch.quality = kernels::QualityReport{};
  r.channels.push_back(ch);
  const auto rows = io::summary_rows(r);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].quality, "");
  EXPECT_EQ(rows[1].quality, "ok");
  const fs::path dir = test::fresh_dir("quality_unscreened");
  io::write_lot_summary(dir, rows);
  const auto csv = read_csv(dir / "lot_summary.csv");
  ASSERT_EQ(csv.size(), 2u);
  for (const char* c : {"quality", "n_missing", "n_spikes", "longest_run", "max_spike_sigmas"})
    EXPECT_EQ(csv[0].at(c), "") << c;
  EXPECT_EQ(csv[1].at("n_spikes"), "0");
  EXPECT_EQ(csv[1].at("quality"), "ok");
}

TEST(QualityCommand, InjectedSaturationAndSpikesAreFoundWrittenReportedAndFailTheSpec) {
  const fs::path dir = test::fresh_dir("quality_command");
  write_recording(dir / "SN7.h5");
  std::ofstream(dir / "spec.json")
      << R"j({"channels": {"gyro_*": {"quality": {"max_spikes": 0, "saturation": "fail"}}}})j";
  std::string out;
  run_command(binary() + " analyze --no-psd -o " + (dir / "out").string() + " --spec " +
                  (dir / "spec.json").string() + " " + (dir / "SN7.h5").string(),
              &out);
  EXPECT_NE(out.find("quality flags (1): SN7:/imu/gyro_x (saturation;spikes)"), std::string::npos)
      << out;

  const io::RecordingResult r = io::read_results(dir / "out" / "SN7.allan.h5");
  ASSERT_EQ(r.channels.size(), 2u);
  ASSERT_TRUE(r.channels[0].quality);
  const kernels::QualityReport& q = *r.channels[0].quality;
  EXPECT_EQ(q.flags, "saturation;spikes");
  EXPECT_EQ(q.n_saturated_runs, 1);
  EXPECT_EQ(q.n_saturated_samples, 50);
  EXPECT_EQ(q.n_stuck_runs, 0);  // a clipped stretch is saturation, not stuck output
  EXPECT_EQ(q.first_saturated, 30'000);
  EXPECT_EQ(q.n_spikes, 3);
  EXPECT_EQ(q.first_spike, 10'000);
  ASSERT_TRUE(r.channels[1].quality);
  EXPECT_EQ(r.channels[1].quality->flags, "");

  const auto rows = read_csv(dir / "out" / "lot_summary.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("channel"), "/imu/gyro_x");
  EXPECT_EQ(rows[0].at("quality"), "saturation;spikes");
  EXPECT_EQ(rows[0].at("n_saturated"), "50");
  EXPECT_EQ(rows[0].at("n_spikes"), "3");
  EXPECT_EQ(rows[0].at("n_missing"), "0");
  EXPECT_EQ(rows[0].at("spec_status"), "fail");
  EXPECT_EQ(rows[0].at("spec_detail"), "quality: 3 spikes > 0; 50 saturated samples > 0");
  EXPECT_EQ(rows[1].at("quality"), "ok");
  EXPECT_EQ(rows[1].at("spec_status"), "pass");
  const auto h5rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(h5rows.size(), 2u);
  EXPECT_EQ(h5rows[0].quality, "saturation;spikes");
  EXPECT_EQ(h5rows[0].n_spikes, 3);

  ASSERT_EQ(run_command(binary() + " report " + (dir / "out").string() + " -o " +
                            (dir / "report.html").string(),
                        &out),
            0)
      << out;
  std::ifstream html(dir / "report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("Data quality"), std::string::npos);
  EXPECT_NE(page.find("1 of 2 channels screened raise a flag"), std::string::npos);
  EXPECT_NE(page.find("<span class=\"bad\">3 spikes at sample 10000"), std::string::npos);
}

}  // namespace
}  // namespace allanlot
