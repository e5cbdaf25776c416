// The lot summary: statistics against hand-computed values, the outlier rule on a lot with a
// planted outlier, manifest entries without results, the files write_lot leaves behind, and the
// whole path through the binary (simulate a lot, analyze --spec, summarize --spec --manifest).
#include "io/results.hpp"
#include "kernels/uncertainty/chi2.hpp"
#include "src/lot/statistics.hpp"
#include "src/lot/summary.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

io::SummaryRow row(const std::string& device, const std::string& channel, double n_value) {
  io::SummaryRow r{
      device, channel, "deg/s", 1000, io::ChannelStatus::ok(), "/data/" + device + ".h5"};
  r.value[3] = n_value;
  r.sigma[3] = 0.01;
  r.unit[3] = "deg/h/sqrt(Hz)";
  r.detected[3] = 1;
  return r;
}

const io::StatisticsRow& find(const std::vector<io::StatisticsRow>& s, const std::string& channel,
                              const std::string& term) {
  for (const auto& x : s)
    if (x.channel == channel && x.term == term) return x;
  throw std::runtime_error("no statistics for " + channel + " " + term);
}

TEST(LotSummary, QuantilesAreHyndmanFanType7) {
  // h = (n - 1) p on {1, 2, 3, 4}: p = 0.25 -> h = 0.75 -> 1 + 0.75 * 1.
  const std::vector<double> v{1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(v, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(v, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(v, 0.95), 3.85);  // h = 2.85
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(v, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(lot::quantile_sorted(std::vector<double>{7}, 0.3), 7.0);
  EXPECT_THROW(lot::quantile_sorted(std::vector<double>{}, 0.5), std::invalid_argument);
}

TEST(LotSummary, StatisticsMatchHandComputedValues) {
  // N of gyro_x over five units: 10, 11, 12, 13, 50.
  //   median 12; |x - 12| = 2, 1, 0, 1, 38 -> sorted 0, 1, 1, 2, 38 -> MAD 1, spread 1.4826;
  //   p5: h = 0.2 -> 10.2; p25: h = 1 -> 11; p75: h = 3 -> 13; p95: h = 3.8 -> 13 + 0.8 * 37.
  //   z of 50 = 38 / hypot(1.4826, 0.01) = 25.6 > 3.5: the only outlier (z of 10 is -1.35).
  std::vector<io::SummaryRow> rows;
  const double n[] = {12, 50, 10, 13, 11};  // order of the rows does not matter
  for (int i = 0; i < 5; ++i)
    rows.push_back(row("U" + std::to_string(i), "/imu/gyro_x", n[i]));
  rows[3].detected[3] = 0;
  rows.push_back(
      {"BAD", "", "", 0, io::ChannelStatus::failed("unreadable"), "/data/bad.h5"});  // not counted
  auto failed = row("U5", "/imu/gyro_x", 1000.0);
  failed.status = io::ChannelStatus::failed("too short");  // a failed channel's numbers never enter
  rows.push_back(failed);
  const auto stats = lot::lot_statistics(rows);
  ASSERT_EQ(stats.size(), 1u);
  const auto& s = find(stats, "/imu/gyro_x", "N");
  EXPECT_EQ(s.unit, "deg/h/sqrt(Hz)");
  EXPECT_EQ(s.n, 5);
  EXPECT_EQ(s.n_detected, 4);
  EXPECT_DOUBLE_EQ(s.median, 12.0);
  EXPECT_DOUBLE_EQ(s.spread, 1.4826);
  EXPECT_DOUBLE_EQ(s.p5, 10.2);
  EXPECT_DOUBLE_EQ(s.p25, 11.0);
  EXPECT_DOUBLE_EQ(s.p75, 13.0);
  EXPECT_DOUBLE_EQ(s.p95, 13.0 + 0.8 * 37.0);
  EXPECT_EQ(s.min, 10.0);
  EXPECT_EQ(s.max, 50.0);
  EXPECT_EQ(s.n_outliers, 1);
  for (const auto& r : rows)
    EXPECT_EQ(r.outlier, r.device_id == "U1" ? 1 : 0) << r.device_id;
  EXPECT_EQ(rows[1].outlier_terms, "N z=+26");
}

// x_i = mu + sd Phi^-1((i + 0.5) / n): a lot of n units that scatters exactly as a normal
// sample should, without the luck of a random draw (a seeded draw of 21 can have a MAD 40 %
// below its expectation and then honestly flag its own tails).
double normal_score(int i, int n) {
  const double p = (i + 0.5) / n;
  if (2 * i + 1 == n) return 0.0;  // the median
  const double z = std::sqrt(kernels::chi2_quantile(std::abs(2 * p - 1), 1.0));
  return p < 0.5 ? -z : z;
}

TEST(LotSummary, PlantedOutlierIsTheOnlyOneFlagged) {
  // Twenty-one units whose N scatters normally by 0.5 around 18 and whose B by 0.3 around 4.5
  // (B in another order, so that the units differ), then unit 7 given N 10 sigma high: the
  // robust scale is not inflated by it, and it alone is flagged.
  const int n = 21;
  std::vector<io::SummaryRow> rows;
  for (int i = 0; i < n; ++i) {
    auto r = row('U' + std::to_string(i), "/imu/gyro_x", 18.0 + 0.5 * normal_score(i, n));
    r.value[2] = 4.5 + 0.3 * normal_score((i * 8) % n, n);
    r.unit[2] = "deg/h";
    r.detected[2] = 1;
    rows.push_back(r);
  }
  rows[7].value[3] = 18.0 + 10 * 0.5;
  const auto stats = lot::lot_statistics(rows);
  EXPECT_EQ(find(stats, "/imu/gyro_x", "N").n_outliers, 1);
  EXPECT_EQ(find(stats, "/imu/gyro_x", "B").n_outliers, 0);
  EXPECT_NEAR(find(stats, "/imu/gyro_x", "N").spread, 0.5, 0.1);  // estimates the scatter
  for (std::size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(rows[i].outlier, i == 7 ? 1 : 0) << i;
  EXPECT_EQ(rows[7].outlier_terms.rfind("N z=+", 0), 0u) << rows[7].outlier_terms;

  // With four units nobody is called an outlier, however far.
  std::vector<io::SummaryRow> small(rows.begin() + 4, rows.begin() + 8);
  lot::lot_statistics(small);
  for (const auto& r : small)
    EXPECT_EQ(r.outlier, 0);
  // MAD 0 (a term fitted as 0 in most units): the units' own sigmas are the scale; 3 +- 0.01
  // among zeros is an outlier, and without any sigma there is no scale at all.
  std::vector<io::SummaryRow> flat;
  for (int i = 0; i < 6; ++i)
    flat.push_back(row("F" + std::to_string(i), "/imu/gyro_x", i == 5 ? 3.0 : 0.0));
  EXPECT_EQ(find(lot::lot_statistics(flat), "/imu/gyro_x", "N").n_outliers, 1);
  for (auto& r : flat)
    r.sigma[3] = 0.0;
  EXPECT_EQ(find(lot::lot_statistics(flat), "/imu/gyro_x", "N").n_outliers, 0);
  // Where most units do not detect the term (fitted at or near 0), nobody is judged on it.
  for (std::size_t i = 0; i < 4; ++i)
    flat[i].detected[3] = 0;
  for (auto& r : flat)
    r.sigma[3] = 0.01;
  EXPECT_EQ(find(lot::lot_statistics(flat), "/imu/gyro_x", "N").n_outliers, 0);
  // A deviation of many robust spreads but within the unit's own uncertainty is no outlier.
  auto noisy = rows;
  noisy[7].sigma[3] = 10 * 0.5;  // 10 lot sigmas away, but only 1 own sigma
  EXPECT_EQ(find(lot::lot_statistics(noisy), "/imu/gyro_x", "N").n_outliers, 0);
}

TEST(LotSummary, KindsAndUnitsAreNeverPooled) {
  std::vector<io::SummaryRow> rows{row("A", "/imu/gyro_x", 1), row("B", "/imu/gyro_x", 3),
                                   row("A", "/imu/gyro_y", 5)};
  auto other = row("C", "/imu/gyro_x", 7);
  other.unit[3] = "deg/sqrt(h)";
  rows.push_back(other);
  const auto stats = lot::lot_statistics(rows);
  ASSERT_EQ(stats.size(), 3u);
  EXPECT_EQ(stats[0].channel, "/imu/gyro_x");
  EXPECT_EQ(stats[0].unit, "deg/h/sqrt(Hz)");
  EXPECT_EQ(stats[0].median, 2.0);
  EXPECT_EQ(stats[1].unit, "deg/sqrt(h)");
  EXPECT_EQ(stats[2].channel, "/imu/gyro_y");
  EXPECT_EQ(stats[2].n, 1);
  EXPECT_EQ(stats[2].spread, 0.0);
}

TEST(LotSummary, ManifestEntriesWithoutResultsAreFailedRows) {
  const auto dir = test::fresh_dir("lot_manifest");
  fs::create_directories(dir / "rec");
  {
    std::ofstream m(dir / "rec" / "manifest.txt");
    m << "# the lot\n\nu1.h5\n  u2.h5  \n" << (dir / "rec" / "u3.h5").string() << "\nu2.h5\n";
  }
  std::vector<io::SummaryRow> rows{row("U1", "/imu/gyro_x", 1)};
  rows[0].source_file = (dir / "rec" / "u1.h5").string();  // analyzed
  io::SummaryRow failed{
      "u3", "", "", 0, io::ChannelStatus::failed("not HDF5"), (dir / "rec" / "u3.h5").string()};
  rows.push_back(failed);  // already reported by this run: not listed twice
  const auto missing = lot::manifest_failures(dir / "rec" / "manifest.txt", rows);
  ASSERT_EQ(missing.size(), 1u);  // u2, once although listed twice
  EXPECT_EQ(missing[0].device_id, "u2");
  EXPECT_EQ(missing[0].channel, "");
  EXPECT_EQ(io::to_string(missing[0].status), "failed: no results file");
  EXPECT_EQ(missing[0].source_file, fs::absolute(dir / "rec" / "u2.h5").string());
  EXPECT_THROW(lot::manifest_failures(dir / "absent.txt", rows), std::runtime_error);
}

TEST(LotSummary, WriteLotWritesSpecColumnsStatisticsAndOverview) {
  const auto dir = test::fresh_dir("lot_write");
  {
    std::ofstream s(dir / "spec.json");
    s << R"j({"name": "test grade",
          "channels": {"gyro_*": {"N": {"max": 0.3, "unit": "deg/sqrt(h)"}}}})j";
    std::ofstream m(dir / "manifest.txt");
    m << "U0.h5\nU1.h5\nU2.h5\nU3.h5\nU4.h5\nU5.h5\ngone.h5\n";
  }
  std::vector<io::SummaryRow> rows;
  const double n[] = {17.0, 17.5, 16.8, 18.5, 17.99, 30.0};  // pass, pass, pass, fail, ?, fail
  for (int i = 0; i < 6; ++i) {
    rows.push_back(row("U" + std::to_string(i), "/imu/gyro_x", n[i]));
    rows.back().source_file = (dir / ("U" + std::to_string(i) + ".h5")).string();
  }
  lot::LotOptions opt;
  opt.spec_path = dir / "spec.json";
  opt.manifest = dir / "manifest.txt";
  std::ostringstream out, err;
  const auto ov = lot::write_lot(dir, rows, opt, out, err);
  EXPECT_EQ(ov.n_units, 7u);
  EXPECT_EQ(ov.n_missing, 1u);
  ASSERT_EQ(ov.kinds.size(), 1u);
  EXPECT_EQ(ov.kinds[0].pass, 3u);
  EXPECT_EQ(ov.kinds[0].fail, 2u);
  EXPECT_EQ(ov.kinds[0].undecided, 1u);
  EXPECT_EQ(ov.kinds[0].outliers, 1u);
  EXPECT_NE(out.str().find("/imu/gyro_x: 3 pass, 2 fail, 1 undecided"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("U5:/imu/gyro_x (N z=+"), std::string::npos) << out.str();
  EXPECT_EQ(err.str(), "");

  const auto back = io::read_lot_summary(dir / "lot_summary.h5");
  ASSERT_EQ(back.size(), 7u);
  EXPECT_EQ(back[0].spec_status, "pass");
  EXPECT_EQ(back[3].spec_status, "fail");
  // In the spec's unit: 18.5 deg/h/sqrt(Hz) = 18.5 / 60 deg/sqrt(h) against 0.3 deg/sqrt(h).
  EXPECT_EQ(back[3].spec_detail.rfind("N 0.308±", 0), 0u) << back[3].spec_detail;
  EXPECT_TRUE(back[3].spec_detail.ends_with(" > 0.3 deg/sqrt(h)")) << back[3].spec_detail;
  EXPECT_EQ(back[4].spec_status, "undecided");
  EXPECT_EQ(back[5].outlier, 1);
  EXPECT_EQ(io::to_string(back[6].status), "failed: no results file");
  EXPECT_EQ(back[6].spec_status, "no data");
  const auto stats = io::read_lot_statistics(dir / "lot_summary.h5");
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].n, 6);
  EXPECT_EQ(stats[0].n_outliers, 1);
  EXPECT_DOUBLE_EQ(stats[0].median, (17.5 + 17.99) / 2);  // 3rd and 4th of 6
  const std::string csv = test::file_bytes(dir / "lot_statistics.csv");
  EXPECT_EQ(csv.rfind("channel,term,unit,n,n_detected,n_outliers,median,spread,p5,p25,p75,p95,"
                      "min,max\n/imu/gyro_x,N,deg/h/sqrt(Hz),6,6,1,17.745,",
                      0),
            0u)
      << csv;

  // A rule that matches nothing is worth a warning; quiet (errors only) prints neither the
  // overview nor the warning.
  {
    std::ofstream s(dir / "spec2.json");
    s << R"j({"channels": {"mag_*": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)"}}}})j";
  }
  opt.spec_path = dir / "spec2.json";
  opt.manifest.clear();
  std::ostringstream out_loud, err_loud;
  lot::write_lot(dir, rows, opt, out_loud, err_loud);
  EXPECT_NE(err_loud.str().find("channels.mag_*: matches no channel"), std::string::npos);
  opt.quiet = true;
  std::ostringstream out2, err2;
  lot::write_lot(dir, rows, opt, out2, err2);
  EXPECT_EQ(out2.str(), "");
  EXPECT_EQ(err2.str(), "");
  EXPECT_EQ(io::read_lot_summary(dir / "lot_summary.h5")[0].spec_status, "no spec");
  // A bad spec stops before anything is written.
  {
    std::ofstream s(dir / "bad.json");
    s << R"j({"channels": {"gyro_*": {"N": {"max": -1, "unit": "deg/h/sqrt(Hz)"}}}})j";
  }
  opt.spec_path = dir / "bad.json";
  fs::remove(dir / "lot_summary.h5");
  EXPECT_THROW(lot::write_lot(dir, rows, opt, out2, err2), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "lot_summary.h5"));
}

// Rule units that do not fit a matched channel are known only once the channels are seen: every
// such problem is reported together, once per rule, term and channel units (not once per unit),
// and nothing is written.
TEST(LotSummary, SpecUnitsThatDoNotFitTheChannelsAreReportedTogether) {
  const auto dir = test::fresh_dir("lot_spec_units");
  {
    std::ofstream s(dir / "spec.json");
    s << R"j({"channels": {"*": {"N": {"max": 20, "unit": "deg/h/sqrt(Hz)"},
                                  "B": {"max": 10, "unit": "deg/h"}}}})j";
  }
  std::vector<io::SummaryRow> rows;
  for (int i = 0; i < 3; ++i) {
    rows.push_back(row("U" + std::to_string(i), "/imu/gyro_x", 18));
    auto accel = row("U" + std::to_string(i), "/imu/accel_x", 0.05);
    accel.units = "m/s^2";
    accel.unit[3] = "mg/sqrt(Hz)";
    accel.value[2] = 0.02;
    accel.sigma[2] = 0.001;
    accel.unit[2] = "mg";
    accel.detected[2] = 1;
    rows.push_back(accel);
  }
  lot::LotOptions opt;
  opt.spec_path = dir / "spec.json";
  std::ostringstream out, err;
  try {
    lot::write_lot(dir, rows, opt, out, err);
    FAIL() << "no error";
  } catch (const spec::Error& e) {
    const std::string spec = (dir / "spec.json").string();
    ASSERT_EQ(e.messages().size(), 2u) << e.what();
    // In the file's order: N, then B.
    EXPECT_EQ(e.messages()[0].rfind(spec + ": channels.*.N.unit: 'deg/h/sqrt(Hz)' is not a unit "
                                           "of N for a 'm/s^2' channel (U0:/imu/accel_x",
                                    0),
              0u)
        << e.messages()[0];
    EXPECT_EQ(e.messages()[1].rfind(spec + ": channels.*.B.unit: 'deg/h' is not a unit of B for a "
                                           "'m/s^2' channel (U0:/imu/accel_x",
                                    0),
              0u)
        << e.messages()[1];
    EXPECT_EQ(std::string(e.what()).rfind(spec + ": 2 errors:\n  " + e.messages()[0], 0), 0u)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "lot_summary.h5"));
  EXPECT_FALSE(fs::exists(dir / "lot_summary.csv"));
}

// The binary: a lot of six simulated two-channel units, one of them given a large N, analysed
// with --spec; then summarize rebuilds the same summary and lists a manifest entry that has
// no results.
TEST(LotSummary, EndToEndThroughTheBinary) {
  const auto dir = test::fresh_dir("lot_e2e");
  // N = 0.005 deg/s*s^0.5 = 18 deg/h/sqrt(Hz); B = 4.5 deg/h; lot spread 5 % on N.
  {
    std::ofstream m(dir / "model.json");
    m << R"j({"sample_rate_hz": 100, "channels": {
          "gyro_x": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.00125}},
          "accel_x": {"units": "m/s^2", "terms": {"N": 0.0005}}},
        "lot_spread": {"N": 0.05}})j";
    std::ofstream s(dir / "spec.json");
    // gyro N = 0.3 deg/sqrt(h), half its limit: pass; accel N = 0.0005 m/s^2*s^0.5 =
    // 0.0005 * 1000 / 9.80665 = 0.051 mg/sqrt(Hz), five times its limit: fail.
    s << R"j({"channels": {
          "gyro_*": {"N": {"max": 0.6, "unit": "deg/sqrt(h)"}},
          "accel_*": {"N": {"max": 0.01, "unit": "mg/sqrt(Hz)"}}}})j";
  }
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " simulate --model " +
                                  (dir / "model.json").string() +
                                  " --lot 6 --duration 120 --seed 5 -o " + (dir / "lot").string(),
                              &out),
            0)
      << out;
  ASSERT_EQ(test::run_command(test::binary() + " analyze --stats oadev --threads 2 --spec " +
                                  (dir / "spec.json").string() + " -o " + (dir / "out").string() +
                                  " @" + (dir / "lot" / "manifest.txt").string(),
                              &out),
            0)
      << out;
  auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 12u);
  for (const auto& r : rows) {
    EXPECT_EQ(io::to_string(r.status), "ok");
    EXPECT_EQ(r.spec_status, r.channel.ends_with("gyro_x") ? "pass" : "fail")
        << r.channel << " " << r.spec_detail;
    // The unit's verdict: its gyro passes, its accelerometer fails, so the unit fails, and says
    // which channel and term.
    EXPECT_EQ(r.unit_spec_status, "fail") << r.device_id;
    EXPECT_EQ(r.unit_spec_detail, "fail: accel_x (N)") << r.device_id;
  }
  EXPECT_NE(out.find("units: 0 pass, 6 fail, 0 undecided"), std::string::npos) << out;
  EXPECT_NE(out.find("units fail: unit_0001 (fail: accel_x (N))"), std::string::npos) << out;
  const std::string csv_head = test::file_bytes(dir / "out" / "lot_summary.csv");
  const std::string header = csv_head.substr(0, csv_head.find('\n'));
  EXPECT_NE(header.find(",unit_spec_status,unit_spec_detail,"), std::string::npos) << header;
  // The power-law levels of clock channels come last (docs/clocks.md), after the low-pass
  // columns; an IMU lot leaves them empty.
  EXPECT_NE(header.find(",lowpass,lowpass_cutoff_hz,lowpass_taps,first_tau_fitted,"
                        "chi2_dof_all_taus,h2,h2_sigma,"),
            std::string::npos)
      << header;
  EXPECT_TRUE(header.ends_with(",hm2,hm2_sigma,hm2_upper,hm2_detected")) << header;
  // The report: the unit's verdict beside it in the unit list, and each channel's verdict cell
  // with the limit it was decided against.
  ASSERT_EQ(test::run_command(test::binary() + " report " + (dir / "out").string(), &out), 0)
      << out;
  const std::string html = test::file_bytes(dir / "out" / "report.html");
  EXPECT_NE(html.find(">unit_0001 <span class=\"fail\">fail: accel_x (N)</span></a>"),
            std::string::npos);
  EXPECT_NE(html.find("<td class=\"verdict fail\"><b>fail</b>: <span class=\"term\">N "),
            std::string::npos);
  EXPECT_NE(html.find(" &gt; 0.01 mg/sqrt(Hz)</span></td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"verdict pass\"><b>pass</b>: <span class=\"term\">N "),
            std::string::npos);
  // In the spec's unit, not the column's deg/h/sqrt(Hz).
  EXPECT_NE(html.find(" &lt;= 0.6 deg/sqrt(h)</span></td>"), std::string::npos);
  EXPECT_EQ(io::read_lot_statistics(dir / "out" / "lot_summary.h5").size() % 2, 0u);

  // summarize from the results alone gives the same rows; a manifest line without results is
  // one more row.
  const std::string summary_before = test::file_bytes(dir / "out" / "lot_summary.csv");
  {
    std::ofstream m(dir / "lot" / "manifest.txt", std::ios::app);
    m << "never_recorded.h5\n";
  }
  // Status 1: a recording of the manifest has no results (a failed input, as in analyze).
  ASSERT_EQ(test::run_command(test::binary() + " summarize " + (dir / "out").string() + " --spec " +
                                  (dir / "spec.json").string() + " --manifest " +
                                  (dir / "lot" / "manifest.txt").string(),
                              &out),
            1)
      << out;
  rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 13u) << out;
  EXPECT_EQ(rows.back().device_id, "never_recorded");
  EXPECT_EQ(io::to_string(rows.back().status), "failed: no results file");
  const std::string summary_after = test::file_bytes(dir / "out" / "lot_summary.csv");
  EXPECT_EQ(summary_after.substr(0, summary_before.size()), summary_before);

  // A bad spec is a usage error found before any recording is analysed: status 2, every
  // problem named with the file and the key, nothing written (not even OUTDIR).
  {
    std::ofstream s(dir / "bad_spec.json");
    s << R"j({"channels": {"gyro_*": {"N": {"max": 0.6, "unit": "furlongs"}},
                          "accel_*": {"N": {"min": 2, "max": 1, "unit": "mg/sqrt(Hz)"}},
                          "[mag": {"B": {"max": 1, "unit": "deg/h"}}},
             "colour": "red"})j";
  }
  const std::vector<std::string> problems = {
      "bad_spec.json: 4 errors:", "bad_spec.json: colour: unknown key",
      "bad_spec.json: channels.gyro_*.N.unit: 'furlongs' is not a unit of N",
      "bad_spec.json: channels.accel_*.N.min: must not exceed max",
      "bad_spec.json: channels.[mag: unknown channel pattern"};
  ASSERT_EQ(test::run_command(test::binary() + " analyze --stats oadev --spec " +
                                  (dir / "bad_spec.json").string() + " -o " +
                                  (dir / "out_bad").string() + " " +
                                  (dir / "lot" / "unit_0001.h5").string(),
                              &out),
            2)
      << out;
  for (const std::string& p : problems)
    EXPECT_NE(out.find(p), std::string::npos) << p << "\n" << out;
  EXPECT_FALSE(fs::exists(dir / "out_bad")) << "analyze wrote before refusing the spec";
  // summarize refuses it before reading a results file: the summary stays as it was.
  const std::string summary_kept = test::file_bytes(dir / "out" / "lot_summary.csv");
  ASSERT_EQ(test::run_command(test::binary() + " summarize " + (dir / "out").string() + " --spec " +
                                  (dir / "bad_spec.json").string(),
                              &out),
            2)
      << out;
  for (const std::string& p : problems)
    EXPECT_NE(out.find(p), std::string::npos) << p << "\n" << out;
  EXPECT_EQ(out.find("unreadable"), std::string::npos) << out;
  EXPECT_EQ(test::file_bytes(dir / "out" / "lot_summary.csv"), summary_kept);
}

}  // namespace
}  // namespace allanlot
