// Results files and lot summaries: written complete or not at all, and read back unchanged.
#include "io/error.hpp"
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace allanlot {
namespace {

io::RecordingResult sample_result() {
  io::RecordingResult r;
  r.device_id = "SN 1";
  r.source_file = "/data/sn1.h5";
  r.tool_version = "0.1.0";
  r.created_utc = "2026-11-22T00:00:00Z";
  r.command_line = "allanlot analyze -o out sn1.h5";
  r.attributes = {{"taus", "octave"}};
  io::ChannelResult ch;
  ch.path = "/imu/gyro_x";
  ch.units = "deg/s";
  ch.sample_rate_hz = 1000;
  ch.n_samples = 5400000;
  ch.n_gaps = 3;
  kernels::StatResult s;
  s.m = {1, 2, 4};
  s.tau_s = {0.001, 0.002, 0.004};
  s.dev = {1e-3, 7e-4, 5e-4};
  s.n = {5399999, 5399997, 5399993};
  ch.stats.emplace_back("oadev", s);
  io::FitRecord fit;
  fit.method = "test";
  fit.status = kernels::FitStatus::Ok;
  fit.rank = 5;
  fit.chi2_dof = 0.97;
  fit.terms.push_back({"N", 0.005, 1e-5, 0.0051, true, "deg/s*s^0.5", 18.0, 0.036, 18.4,
                       "deg/h/sqrt(Hz)", 0.3, "deg/sqrt(h)"});
  fit.terms.push_back({"Q", 0.0, 1e-7, 2e-7, false, "deg", 0.0, 1.7, 3.5, "urad", 0.0, "deg"});
  fit.tau = {0.001, 0.002, 0.004};
  fit.adev_model = {1e-3, 7.1e-4, 5e-4};
  fit.readouts.push_back({"N_1s", true, 0.005, 4e-5, 1.0, 0.00505, 18.0, 0.14, "deg/h/sqrt(Hz)",
                          0.3, 0.0024, "deg/sqrt(h)"});
  ch.fit = fit;
  io::FitRecord pf = fit;  // psd_fit/: the same terms, f and psd_model instead of tau
  pf.tau.clear();
  pf.adev_model.clear();
  pf.readouts.clear();
  pf.f = {0.01, 0.1, 1.0};
  pf.psd_model = {5e-5, 5e-5, 5e-5};
  pf.z_vs_fit = {0.0, 0.0, 0.5, -1.2, 0.1};
  pf.max_abs_z = 1.2;
  pf.worst_term = "N";
  pf.agree = 1;
  ch.psd_fit = pf;
  r.channels.push_back(ch);
  io::ChannelResult bad;
  bad.path = "/imu/temp";
  bad.status = io::ChannelStatus::failed("too short");
  r.channels.push_back(bad);
  return r;
}

TEST(Results, RoundTrip) {
  const auto dir = test::fresh_dir("results_rt");
  const auto path = dir / "SN_1.allan.h5";
  const auto r = sample_result();
  io::write_results(path, r);
  const auto back = io::read_results(path);
  EXPECT_EQ(back.device_id, r.device_id);
  EXPECT_EQ(back.command_line, r.command_line);
  ASSERT_EQ(back.channels.size(), 2u);
  const auto& ch = back.channels[0].path == "/imu/gyro_x" ? back.channels[0] : back.channels[1];
  EXPECT_EQ(ch.units, "deg/s");
  EXPECT_EQ(ch.n_samples, 5400000);
  EXPECT_EQ(ch.n_gaps, 3);
  ASSERT_EQ(ch.stats.size(), 1u);
  EXPECT_EQ(ch.stats[0].first, "oadev");
  EXPECT_EQ(ch.stats[0].second.m, r.channels[0].stats[0].second.m);
  EXPECT_EQ(ch.stats[0].second.dev, r.channels[0].stats[0].second.dev);
  EXPECT_EQ(ch.stats[0].second.n, r.channels[0].stats[0].second.n);
  ASSERT_TRUE(ch.fit.has_value());
  const auto& fit = *ch.fit;
  const auto& want = *r.channels[0].fit;
  EXPECT_EQ(io::to_string(fit.status), "ok");
  EXPECT_EQ(fit.rank, 5);
  EXPECT_EQ(fit.chi2_dof, want.chi2_dof);
  ASSERT_EQ(fit.terms.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(fit.terms[i].term, want.terms[i].term);
    EXPECT_EQ(fit.terms[i].value, want.terms[i].value);
    EXPECT_EQ(fit.terms[i].sigma, want.terms[i].sigma);
    EXPECT_EQ(fit.terms[i].detected, want.terms[i].detected);
    EXPECT_EQ(fit.terms[i].unit_datasheet, want.terms[i].unit_datasheet);
    EXPECT_EQ(fit.terms[i].value_datasheet_alt, want.terms[i].value_datasheet_alt);
  }
  EXPECT_EQ(fit.adev_model, want.adev_model);
  ASSERT_TRUE(ch.psd_fit.has_value());
  const auto& pf = *ch.psd_fit;
  const auto& pwant = *r.channels[0].psd_fit;
  EXPECT_TRUE(pf.tau.empty());
  EXPECT_EQ(pf.f, pwant.f);
  EXPECT_EQ(pf.psd_model, pwant.psd_model);
  EXPECT_EQ(pf.z_vs_fit, pwant.z_vs_fit);
  EXPECT_EQ(pf.max_abs_z, 1.2);
  EXPECT_EQ(pf.worst_term, "N");
  EXPECT_EQ(pf.agree, 1);
  EXPECT_EQ(pf.terms.size(), 2u);
  // The summary row carries the fit in datasheet units.
  const auto rows = io::summary_rows(back);
  const auto& row = rows[0].channel == "/imu/gyro_x" ? rows[0] : rows[1];
  EXPECT_EQ(row.value[3], 18.0);  // N, in the column of N, in its datasheet unit
  EXPECT_EQ(row.unit[3], "deg/h/sqrt(Hz)");
  EXPECT_EQ(row.detected[3], 1);
  EXPECT_EQ(row.value[4], 0.0);  // Q: fitted as zero, not detected
  EXPECT_EQ(row.detected[4], 0);
  EXPECT_EQ(row.fits_agree, 1);
  EXPECT_EQ(row.fits_max_abs_z, 1.2);
  EXPECT_TRUE(std::isnan(row.value[0]));  // R was not in this fit: no value
  EXPECT_EQ(row.chi2_dof, 0.97);
  // Only the final file is left: the temporary was renamed.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(Results, UnwritableDestinationThrowsAndLeavesNothing) {
  const auto dir = test::fresh_dir("results_bad");
  EXPECT_THROW(io::write_results(dir / "no_such_dir" / "x.allan.h5", sample_result()), io::Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(Results, LotSummaryRoundTripAndCsv) {
  const auto dir = test::fresh_dir("summary_rt");
  std::vector<io::SummaryRow> rows = io::summary_rows(sample_result());
  rows.push_back({"broken", "", "", 0, io::ChannelStatus::failed("not an HDF5 file, \"really\""),
                  "/x/broken.h5"});
  rows[0].fits_agree = 0;
  rows[0].fits_max_abs_z = 4.5;
  rows[0].lowpass = "auto";
  rows[0].lowpass_cutoff_hz = 29.2;
  rows[0].first_tau_fitted = 0.9;
  rows[0].chi2_dof_all_taus = 365.7;
  io::write_lot_summary(dir, rows);
  const auto back = io::read_lot_summary(dir / "lot_summary.h5");
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(back[i].device_id, rows[i].device_id);
    EXPECT_EQ(back[i].channel, rows[i].channel);
    EXPECT_EQ(back[i].n_samples, rows[i].n_samples);
    EXPECT_EQ(back[i].status, rows[i].status);
    EXPECT_EQ(back[i].fits_agree, rows[i].fits_agree);
  }
  EXPECT_EQ(back[0].fits_max_abs_z, 4.5);
  EXPECT_TRUE(std::isnan(back[1].fits_max_abs_z));
  const std::string csv = test::file_bytes(dir / "lot_summary.csv");
  EXPECT_EQ(csv.rfind("device_id,channel,units,n_samples,status,source_file,R,R_sigma,R_unit,"
                      "R_detected,K,K_sigma,K_unit,K_detected,B,B_sigma,B_unit,B_detected,N,"
                      "N_sigma,N_unit,N_detected,Q,Q_sigma,Q_unit,Q_detected,chi2_dof,fit_status,"
                      "max_abs_log10_ratio,crosscheck_worst_tau,fits_agree,fits_max_abs_z,"
                      "R_upper,K_upper,B_upper,N_upper,Q_upper,spec_status,spec_detail,outlier,"
                      "outlier_terms,R_spec_status,K_spec_status,B_spec_status,N_spec_status,"
                      "Q_spec_status,readout_N,readout_N_sigma,readout_N_unit,readout_N_alt,"
                      "readout_N_alt_sigma,readout_N_alt_unit,readout_B,readout_B_sigma,"
                      "readout_B_unit,readout_B_tau,readout_K,readout_K_sigma,readout_K_unit,"
                      "readout_K_tau,readouts_valid,quality,n_missing,n_gap_runs,n_time_errors,"
                      "n_saturated,longest_run,n_stuck,n_spikes,max_spike_sigmas,"
                      "unit_spec_status,unit_spec_detail,lowpass,lowpass_cutoff_hz,lowpass_taps,"
                      "first_tau_fitted,chi2_dof_all_taus,h2,h2_sigma,h2_upper,h2_detected,h1,"
                      "h1_sigma,h1_upper,h1_detected,h0,h0_sigma,h0_upper,h0_detected,hm1,"
                      "hm1_sigma,hm1_upper,hm1_detected,hm2,hm2_sigma,hm2_upper,hm2_detected\n",
                      0),
            0u);
  EXPECT_NE(csv.find("SN 1,/imu/gyro_x,deg/s,5400000,ok,/data/sn1.h5,,,,,,,,,,,,,18,0.036,deg/h/"
                     "sqrt(Hz),1,0,1.7,urad,0,0.97,ok,,,0,4.5,,,,18.4,3.5,,,0,,,,,,,18,0.14,"
                     "deg/h/sqrt(Hz),0.3,0.0024,deg/sqrt(h),,,,,,,,,N,,,,,,,,,,,,auto,29.2,,0.9,"
                     "365.7,,,,,,,,,,,,,,,,,,,,\n"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\"failed: not an HDF5 file, \"\"really\"\"\""), std::string::npos);
}

}  // namespace
}  // namespace allanlot
