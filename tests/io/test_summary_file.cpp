// The summary side of io: the summary-only results reader agrees with the full reader, the new
// lot-summary columns round-trip, and lot_summary.h5 files written before those columns (or
// before /statistics) still read.
#include "io/error.hpp"
#include "io/results.hpp"
#include "io/seal.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>

namespace allanlot {
namespace {

bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

void expect_same_rows(const io::SummaryRow& a, const io::SummaryRow& b) {
  EXPECT_EQ(a.device_id, b.device_id);
  EXPECT_EQ(a.channel, b.channel);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.n_samples, b.n_samples);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.source_file, b.source_file);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_TRUE(same(a.value[i], b.value[i])) << a.channel << " term " << i;
    EXPECT_TRUE(same(a.sigma[i], b.sigma[i])) << a.channel << " term " << i;
    EXPECT_TRUE(same(a.upper[i], b.upper[i])) << a.channel << " term " << i;
    EXPECT_EQ(a.unit[i], b.unit[i]);
    EXPECT_EQ(a.detected[i], b.detected[i]);
  }
  EXPECT_TRUE(same(a.chi2_dof, b.chi2_dof));
  EXPECT_TRUE(same(a.max_abs_log10_ratio, b.max_abs_log10_ratio));
  EXPECT_TRUE(same(a.crosscheck_worst_tau, b.crosscheck_worst_tau));
  EXPECT_EQ(a.fits_agree, b.fits_agree);
  EXPECT_TRUE(same(a.fits_max_abs_z, b.fits_max_abs_z));
}

io::FitRecord fit_of(double n_ds) {
  io::FitRecord fit;
  fit.method = "test";
  fit.status = kernels::FitStatus::Ok;
  fit.rank = 5;
  fit.chi2_dof = 1.1;
  fit.terms.push_back({"B", 1e-3, 1e-5, 0.0, true, "deg/s", 3.6, 0.036, 0.0, "deg/h", 0.0, ""});
  fit.terms.push_back({"N", 0.005, 1e-5, 0.0051, true, "deg/s*s^0.5", n_ds, 0.036, 18.4,
                       "deg/h/sqrt(Hz)", 0.3, "deg/sqrt(h)"});
  fit.terms.push_back({"Q", 0.0, 1e-7, 2e-7, false, "deg", 0.0, 1.7, 3.5, "urad", 0.0, "deg"});
  fit.tau = {0.1, 0.2};
  fit.adev_model = {1e-3, 7e-4};
  return fit;
}

// Channels at several depths, one failed, one without psd_fit/crosscheck, statistics that the
// summary reader must not need.
io::RecordingResult lot_unit() {
  io::RecordingResult r;
  r.device_id = "SN 7";
  r.source_file = "/data/sn7.h5";
  r.tool_version = "test";
  io::ChannelResult a;
  a.path = "/imu/gyro_x";
  a.units = "deg/s";
  a.sample_rate_hz = 100;
  a.n_samples = 12000;
  kernels::StatResult s;
  s.m = {1, 2, 4};
  s.tau_s = {0.01, 0.02, 0.04};
  s.dev = {1e-3, 7e-4, 5e-4};
  s.n = {11999, 11997, 11993};
  a.stats.emplace_back("oadev", s);
  a.stats.emplace_back("mdev", s);
  a.fit = fit_of(18.0);
  io::FitRecord pf = fit_of(18.2);
  pf.tau.clear();
  pf.adev_model.clear();
  pf.f = {0.1, 1.0};
  pf.psd_model = {5e-5, 5e-5};
  pf.z_vs_fit = {0.5, -1.2, 0.1};
  pf.max_abs_z = 1.2;
  pf.worst_term = "N";
  pf.agree = 1;
  a.psd_fit = pf;
  io::PsdRecord psd;
  psd.method = "welch";
  psd.f = {0.1, 1.0};
  psd.psd = {1e-4, 1e-4};
  psd.edf = {10, 100};
  psd.n_avg = {1, 10};
  a.psd = psd;
  io::CrosscheckRecord cc;
  cc.tau = {0.01, 0.02};
  cc.avar_time = {1e-6, 5e-7};
  cc.avar_psd = {1.1e-6, 5e-7};
  cc.ratio = {1.1, 1.0};
  cc.valid = {1, 1};
  cc.max_abs_log10_ratio = 0.0414;
  cc.valid_tau_range = {0.01, 0.02};
  cc.worst_tau = 0.01;
  a.crosscheck = cc;
  r.channels.push_back(a);
  io::ChannelResult b = a;
  b.path = "/deep/er/accel_z";
  b.units = "m/s^2";
  b.psd_fit.reset();
  b.crosscheck.reset();
  b.psd.reset();
  r.channels.push_back(b);
  io::ChannelResult bad;
  bad.path = "/imu/temp";
  bad.status = io::ChannelStatus::failed("too short");
  r.channels.push_back(bad);
  return r;
}

TEST(SummaryIo, SummaryReaderAgreesWithFullReader) {
  const auto dir = test::fresh_dir("summary_reader");
  const auto path = dir / "SN_7.allan.h5";
  io::write_results(path, lot_unit());
  const auto full = io::summary_rows(io::read_results(path));
  const auto fast = io::summary_rows(io::read_summary_results(path));
  ASSERT_EQ(full.size(), 3u);
  ASSERT_EQ(fast.size(), full.size());
  for (std::size_t i = 0; i < full.size(); ++i)
    expect_same_rows(fast[i], full[i]);
  // And the numbers are the ones written, the upper bound included.
  const auto& g = full[0].channel == "/imu/gyro_x" ? full[0] : full[1];
  EXPECT_EQ(g.value[3], 18.0);
  EXPECT_EQ(g.upper[3], 18.4);
  EXPECT_EQ(g.fits_agree, 1);
  EXPECT_EQ(g.max_abs_log10_ratio, 0.0414);
  EXPECT_THROW(io::read_summary_results(dir / "absent.allan.h5"), io::Error);
}

TEST(SummaryIo, SummaryReaderNeverOpensTheStatistics) {
  // With a dataset of allan/ and of psd/ removed, the full reader fails and the summary reader
  // does not: it does not open them.
  const auto dir = test::fresh_dir("summary_reader_skip");
  const auto path = dir / "SN_7.allan.h5";
  io::write_results(path, lot_unit());
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Ldelete(f, "/imu/gyro_x/allan/oadev/dev", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(f, "/imu/gyro_x/psd/psd", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  io::reseal_file(path);  // the seal is checked first; this test is about what is opened
  EXPECT_THROW(io::read_results(path), io::Error);
  EXPECT_EQ(io::summary_rows(io::read_summary_results(path)).size(), 3u);
}

TEST(SummaryIo, NewColumnsRoundTrip) {
  const auto dir = test::fresh_dir("summary_new_cols");
  auto rows = io::summary_rows(lot_unit());
  rows[0].spec_status = "fail";
  rows[0].spec_detail = "N 18.3±0.04 > 18 deg/h/sqrt(Hz)";
  rows[0].outlier = 1;
  rows[0].outlier_terms = "N z=+5.1";
  rows[0].spec_term_status[3] = "fail";
  io::StatisticsRow st;
  st.channel = "/imu/gyro_x";
  st.term = "N";
  st.unit = "deg/h/sqrt(Hz)";
  st.n = 6;
  st.n_detected = 5;
  st.n_outliers = 1;
  st.median = 18;
  st.spread = 0.5;
  st.p5 = 17.1;
  st.p25 = 17.6;
  st.p75 = 18.3;
  st.p95 = 19.0;
  st.min = 17.0;
  st.max = 21.0;
  io::write_lot_summary(dir, rows, {st}, {{"spec_file", "/x/spec.json"}});
  const auto back = io::read_lot_summary(dir / "lot_summary.h5");
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    expect_same_rows(back[i], rows[i]);
    EXPECT_EQ(back[i].spec_status, rows[i].spec_status);
    EXPECT_EQ(back[i].spec_detail, rows[i].spec_detail);
    EXPECT_EQ(back[i].outlier, rows[i].outlier);
    EXPECT_EQ(back[i].outlier_terms, rows[i].outlier_terms);
    EXPECT_EQ(back[i].spec_term_status, rows[i].spec_term_status);
  }
  const auto sback = io::read_lot_statistics(dir / "lot_summary.h5");
  ASSERT_EQ(sback.size(), 1u);
  EXPECT_EQ(sback[0].channel, st.channel);
  EXPECT_EQ(sback[0].unit, st.unit);
  EXPECT_EQ(sback[0].n_detected, 5);
  EXPECT_EQ(sback[0].p95, 19.0);
  EXPECT_EQ(sback[0].max, 21.0);
  EXPECT_NE(test::file_bytes(dir / "lot_summary.csv").find(",fail,N 18.3±0.04 > 18 "),
            std::string::npos);
  EXPECT_EQ(test::file_bytes(dir / "lot_statistics.csv"),
            "channel,term,unit,n,n_detected,n_outliers,median,spread,p5,p25,p75,p95,min,max\n"
            "/imu/gyro_x,N,deg/h/sqrt(Hz),6,5,1,18,0.5,17.1,17.6,18.3,19,17,21\n");
}

// A /summary as the first release wrote it: fewer columns, no /statistics.
TEST(SummaryIo, ReadsLotSummaryWrittenBeforeTheNewColumns) {
  const auto dir = test::fresh_dir("summary_old");
  const auto path = dir / "lot_summary.h5";
  struct Old {
    const char* device_id;
    const char* channel;
    const char* units;
    std::int64_t n_samples;
    const char* status;
    const char* source_file;
    double N;
    double N_sigma;
    const char* N_unit;
    std::uint8_t N_detected;
    double chi2_dof;
    double max_abs_log10_ratio;
  };
  const Old recs[2] = {{"SN1", "/imu/gyro_x", "deg/s", 100, "ok", "/d/sn1.h5", 18.0, 0.03,
                        "deg/h/sqrt(Hz)", 1, 0.9, 0.02},
                       {"SN2", "", "", 0, "failed: unreadable", "/d/sn2.h5", std::nan(""),
                        std::nan(""), "", 0, std::nan(""), std::nan("")}};
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t str = H5Tcopy(H5T_C_S1);
    H5Tset_size(str, H5T_VARIABLE);
    const hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(Old));
    H5Tinsert(t, "device_id", offsetof(Old, device_id), str);
    H5Tinsert(t, "channel", offsetof(Old, channel), str);
    H5Tinsert(t, "units", offsetof(Old, units), str);
    H5Tinsert(t, "n_samples", offsetof(Old, n_samples), H5T_NATIVE_INT64);
    H5Tinsert(t, "status", offsetof(Old, status), str);
    H5Tinsert(t, "source_file", offsetof(Old, source_file), str);
    H5Tinsert(t, "N", offsetof(Old, N), H5T_NATIVE_DOUBLE);
    H5Tinsert(t, "N_sigma", offsetof(Old, N_sigma), H5T_NATIVE_DOUBLE);
    H5Tinsert(t, "N_unit", offsetof(Old, N_unit), str);
    H5Tinsert(t, "N_detected", offsetof(Old, N_detected), H5T_NATIVE_UINT8);
    H5Tinsert(t, "chi2_dof", offsetof(Old, chi2_dof), H5T_NATIVE_DOUBLE);
    H5Tinsert(t, "max_abs_log10_ratio", offsetof(Old, max_abs_log10_ratio), H5T_NATIVE_DOUBLE);
    const hsize_t n = 2;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t ds = H5Dcreate2(f, "summary", t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, recs), 0);
    H5Dclose(ds);
    H5Sclose(space);
    H5Tclose(t);
    H5Tclose(str);
    H5Fclose(f);
  }
  const auto rows = io::read_lot_summary(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].device_id, "SN1");
  EXPECT_EQ(rows[0].value[3], 18.0);
  EXPECT_EQ(rows[0].unit[3], "deg/h/sqrt(Hz)");
  EXPECT_EQ(rows[0].chi2_dof, 0.9);
  EXPECT_EQ(io::to_string(rows[1].status), "failed: unreadable");
  for (const auto& r : rows) {
    EXPECT_TRUE(std::isnan(r.value[0]));  // R was never a column of this file
    EXPECT_EQ(r.unit[0], "");
    EXPECT_TRUE(std::isnan(r.crosscheck_worst_tau));
    EXPECT_EQ(r.fits_agree, -1);
    EXPECT_TRUE(std::isnan(r.fits_max_abs_z));
    for (double u : r.upper)
      EXPECT_TRUE(std::isnan(u));
    EXPECT_EQ(r.spec_status, "");
    EXPECT_EQ(r.spec_detail, "");
    EXPECT_EQ(r.outlier, 0);
    EXPECT_EQ(r.outlier_terms, "");
    EXPECT_EQ(r.spec_term_status[3], "");
  }
  EXPECT_TRUE(io::read_lot_statistics(path).empty());
}

// CSV injection (OWASP): a cell a spreadsheet would run as a formula starts with a single quote
// and is quoted; numbers, and text that starts otherwise, are as they were.
TEST(SummaryIo, CsvCellsThatWouldBeFormulasAreNeutralised) {
  EXPECT_EQ(io::csv_field("=HYPERLINK(\"http://x\",\"y\")"),
            "\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\"");
  EXPECT_EQ(io::csv_field("+cmd|' /C calc'!A0"), "\"'+cmd|' /C calc'!A0\"");
  EXPECT_EQ(io::csv_field("@SUM(1+1)"), "\"'@SUM(1+1)\"");
  EXPECT_EQ(io::csv_field("-2+3"), "\"'-2+3\"");
  EXPECT_EQ(io::csv_field("\tx"), "\"'\tx\"");
  EXPECT_EQ(io::csv_field("\rx"), "\"'\rx\"");
  EXPECT_EQ(io::csv_field("-1.5e-3"), "-1.5e-3");
  EXPECT_EQ(io::csv_field("+7"), "+7");
  EXPECT_EQ(io::csv_field("unit=7"), "unit=7");
  EXPECT_EQ(io::csv_field("/imu/gyro_x"), "/imu/gyro_x");
  EXPECT_EQ(io::csv_field(""), "");
}

TEST(SummaryIo, ADeviceIdThatIsAFormulaIsTextInLotSummaryCsv) {
  const auto dir = test::fresh_dir("summary_io_formula");
  io::SummaryRow row{"=HYPERLINK(\"http://evil\")", "/imu/gyro_x", "deg/s", 100,
                     io::ChannelStatus::ok(),       "in/unit.h5"};
  io::write_lot_summary(dir, {row});
  std::ifstream in(dir / "lot_summary.csv");
  std::string header, line;
  std::getline(in, header);
  std::getline(in, line);
  EXPECT_TRUE(line.starts_with("\"'=HYPERLINK(")) << line;
}

}  // namespace
}  // namespace allanlot
