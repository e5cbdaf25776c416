// The schema owner (io/schema.hpp): every line of every table round-trips through the writer
// and the readers, a file of a newer schema_version is refused naming the file, and the
// statuses print and parse both ways at the file boundary (docs/formats.md "Results file
// layout", "Lot summary").
#include "io/error.hpp"
#include "io/results.hpp"
#include "io/schema.hpp"
#include "io/seal.hpp"
#include "io/status.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using kernels::FitStatus;

// Every field of `table` in `got` equals `want`, and `want` differs from a default-constructed
// record in every field (so that a field the writer or a reader drops is noticed).
template <class Rec, class Table>
void expect_fields(const Rec& want, const Rec& got, const Table& table, const std::string& where,
                   bool summary_only = false) {
  // Static: GCC 12 at -O2 flags the automatic one as maybe-uninitialized (a false positive that
  // broke the dev build; the value is the same default-constructed record).
  static const Rec blank{};
  for (const auto& f : table) {
    if (summary_only && !f.summary) continue;
    std::visit(
        [&](auto m) {
          EXPECT_FALSE(want.*m == blank.*m)
              << where << ": test data leaves '" << f.name << "' at its default";
          EXPECT_TRUE(want.*m == got.*m) << where << ": field '" << f.name << "' changed";
        },
        f.member);
  }
}

kernels::StatResult stat() {
  kernels::StatResult s;
  s.m = {1, 2, 4};
  s.tau_s = {0.001, 0.002, 0.004};
  s.dev = {1e-3, 7e-4, 5e-4};
  s.n = {99, 97, 93};
  s.edf = {90.5, 40.25, 20.125};
  s.dev_lo = {9e-4, 6e-4, 4e-4};
  s.dev_hi = {1.1e-3, 8e-4, 6e-4};
  s.alpha = {0, -1, -2};
  s.confidence = 0.683;
  return s;
}

io::FitRecord fit(bool psd_domain) {
  io::FitRecord f;
  f.method = psd_domain ? "psd method" : "allan method";
  f.status = psd_domain ? FitStatus::RankDeficient : FitStatus::Ok;
  f.rank = psd_domain ? 4 : 5;
  f.chi2_dof = 0.97;
  f.terms.push_back({"N", 0.005, 1e-5, 0.0051, true, "deg/s*s^0.5", 18.0, 0.036, 18.4,
                     "deg/h/sqrt(Hz)", 0.3, "deg/sqrt(h)"});
  f.terms.push_back({"Q", 1e-9, 1e-7, 2e-7, false, "deg", 1e-3, 1.7, 3.5, "urad", 2e-3, "deg"});
  f.tau = {0.001, 0.002};
  f.adev_model = {1e-3, 7.1e-4};
  f.f = {0.01, 0.1};
  f.psd_model = {5e-5, 4e-5};
  f.z_vs_fit = {0.5, -1.2};
  f.max_abs_z = 1.2;
  f.worst_term = "N";
  f.agree = 1;
  f.lowpass = "auto";
  f.lowpass_cutoff_hz = 29.2;
  f.lowpass_taps = 1.24;
  f.lowpass_delta_ic = 6197.7;
  f.first_tau_fitted = 0.002;
  f.taus_fitted = 1;
  f.chi2_dof_all_taus = 365.7;
  f.readouts.push_back({"N_1s", true, 0.005, 4e-5, 1.0, 0.00505, 18.0, 0.14, "deg/h/sqrt(Hz)", 0.3,
                        0.0024, "deg/sqrt(h)"});
  f.readouts.push_back(
      {"K_3s", false, 1e-6, 1e-7, 3.0, 2e-6, 0.1, 0.01, "deg/h/sqrt(h)", 0.0, 0.0, ""});
  f.model = "eq. (3) + lowpass 1.15 taps, resonance 0.567 Hz";
  f.model_gap = 0.733;
  f.model_gap_p95 = 1.41;
  f.model_replicas = 19;
  f.model_within_noise = 1;
  f.effects.push_back({0, "lowpass", "taps", 1.15, 0.01, 0});
  f.effects.push_back({1, "resonance", "frequency_hz", 0.567, 1e-4, 1});
  return f;
}

io::DiagnosisRecord diagnosis() {
  io::DiagnosisRecord d;
  d.channel = "/imu/gyro_x";
  d.m = {1, 10};
  d.tau = {0.01, 0.1};
  d.avar_measured = {1e-6, 2e-7};
  d.edf = {100, 10};
  d.avar_model_before = {1.1e-6, 1.9e-7};
  d.avar_model_after = {1e-6, 2e-7};
  d.mc_before_lo = {9e-7, 1e-7};
  d.mc_before_hi = {1.2e-6, 3e-7};
  d.mc_after_lo = {8e-7, 1.5e-7};
  d.mc_after_hi = {1.3e-6, 2.5e-7};
  d.z_before = {2.5, 0.1};
  d.z_after = {0.2, 0.1};
  d.significant_before = {1, 0};
  d.significant_after = {0, 0};
  d.effect = {"sinusoid"};
  d.parameters_json = {"{}"};
  d.gap_before = {4.2};
  d.gap_after = {1.05};
  d.delta_ic = {-120};
  d.number_attributes = {{"gap_after", 1.05}, {"gap_before", 4.2}};
  d.string_attributes = {{"model_after", "{}"}, {"source_file", "x.h5"}};
  return d;
}

kernels::QualityReport quality() {
  kernels::QualityReport q;
  q.n_samples = 5400000;
  q.n_missing = 3;
  q.n_gap_runs = 2;
  q.first_gap = 17;
  q.n_duplicate_times = 4;
  q.first_duplicate_time = 5;
  q.n_decreasing_times = 6;
  q.first_decreasing_time = 7;
  q.n_saturated_runs = 8;
  q.n_saturated_samples = 90;
  q.first_saturated = 100;
  q.longest_run = 110;
  q.longest_run_start = 120;
  q.stuck_run = 13;
  q.n_stuck_runs = 14;
  q.first_stuck = 150;
  q.p_equal = 0.25;
  q.p_continue = 0.375;
  q.n_spikes = 16;
  q.first_spike = 170;
  q.max_spike_sigmas = 18.5;
  q.spike_window = 31;
  q.flags = "gaps;time_stamps;saturation;stuck;spikes";
  return q;
}

io::RecordingResult every_field() {
  io::RecordingResult r;
  r.device_id = "SN 1";
  r.source_file = "/data/sn1.h5";
  r.tool_version = "0.1.0";
  r.created_utc = "2026-11-22T00:00:00Z";
  r.command_line = "allanlot analyze -o out sn1.h5";
  io::ChannelResult ch;
  ch.path = "/imu/gyro_x";
  ch.units = "deg/s";
  ch.sample_rate_hz = 1000;
  ch.n_samples = 5400000;
  ch.n_gaps = 3;
  ch.data_type = "phase";
  ch.gap_policy = "fill:10";
  ch.n_filled = 2;
  ch.filled_runs = 1;
  ch.gap_runs_left = 1;
  ch.data_max = 2.5;
  ch.data_min = -1.5;
  ch.data_mean = 0.25;
  ch.status = io::ChannelStatus::failed("partly: a note");
  ch.notes = "totdev skipped";
  ch.stats.emplace_back("oadev", stat());
  ch.fit = fit(false);
  ch.psd_fit = fit(true);
  io::PsdRecord psd;
  psd.method = "welch";
  psd.convention = "two-sided for the test";
  psd.f = {0.1, 1};
  psd.psd = {1e-5, 2e-5};
  psd.edf = {10, 20};
  psd.n_avg = {3, 4};
  ch.psd = psd;
  io::CrosscheckRecord c;
  c.tau = {0.1, 1};
  c.avar_time = {1e-6, 1e-7};
  c.avar_psd = {1.1e-6, 0.9e-7};
  c.ratio = {1.1, 0.9};
  c.valid = {1, 0};
  c.max_abs_log10_ratio = 0.04;
  c.valid_tau_range = {0.1, 0.1};
  c.worst_tau = 0.1;
  ch.crosscheck = c;
  ch.diagnosis = diagnosis();
  ch.quality = quality();
  io::PowerLawRecord pl;
  pl.method = "nnls";
  pl.status = "ok";
  pl.levels = {{2, "white PM", 1e-21, 2e-22, 1.5e-21, true},
               {0, "white FM", 0, 1e-23, 3e-23, false}};
  pl.tau = {1, 2};
  pl.adev_model = {1e-11, 7e-12};
  pl.mdev_tau = {1};
  pl.mdev_model = {1e-11};
  ch.powerlaw = pl;
  r.channels.push_back(ch);
  return r;
}

template <class Row, class Columns>
void expect_columns(const std::vector<Row>& want, const std::vector<Row>& got,
                    const Columns& columns, const std::string& where) {
  ASSERT_EQ(want.size(), got.size()) << where;
  const Row blank{};
  for (const auto& c : columns)
    std::visit(
        [&](auto m) {
          bool filled = false;
          for (std::size_t i = 0; i < want.size(); ++i) {
            filled = filled || !(want[i].*m == blank.*m);
            EXPECT_TRUE(want[i].*m == got[i].*m) << where << " row " << i << ": " << c.name;
          }
          EXPECT_TRUE(filled) << where << ": test data leaves " << c.name << " at its default";
        },
        c.member);
}

TEST(Schema, EveryTableLineRoundTrips) {
  const fs::path path = test::fresh_dir("schema_rt") / "SN_1.allan.h5";
  const io::RecordingResult r = every_field();
  io::write_results(path, r);
  const io::RecordingResult back = io::read_results(path);
  namespace s = io::schema;
  expect_fields(r, back, s::root_fields(), "/");
  ASSERT_EQ(back.channels.size(), 1u);
  const io::ChannelResult &want = r.channels[0], &got = back.channels[0];
  EXPECT_EQ(got.path, want.path);
  expect_fields(want, got, s::channel_fields(), want.path);
  ASSERT_EQ(got.stats.size(), 1u);
  EXPECT_EQ(got.stats[0].first, "oadev");
  expect_fields(want.stats[0].second, got.stats[0].second, s::stat_fields(), "allan/oadev");
  for (const auto& [w, g, name] : {std::tuple{&want.fit, &got.fit, "fit"},
                                   std::tuple{&want.psd_fit, &got.psd_fit, "psd_fit"}}) {
    ASSERT_TRUE(g->has_value()) << name;
    expect_fields(**w, **g, s::fit_fields(), name);
    expect_columns((*w)->terms, (*g)->terms, s::term_columns(), name);
    expect_columns((*w)->readouts, (*g)->readouts, s::readout_columns(), name);
    expect_columns((*w)->effects, (*g)->effects, s::effect_columns(), name);
  }
  ASSERT_TRUE(got.psd && got.crosscheck && got.diagnosis);
  expect_fields(*want.psd, *got.psd, s::psd_fields(), "psd");
  expect_fields(*want.crosscheck, *got.crosscheck, s::crosscheck_fields(), "crosscheck");
  expect_fields(*want.diagnosis, *got.diagnosis, s::diagnosis_fields(), "diagnosis");
  ASSERT_TRUE(got.quality);
  expect_fields(*want.quality, *got.quality, s::quality_fields(), "quality");
  ASSERT_TRUE(got.powerlaw);
  expect_fields(*want.powerlaw, *got.powerlaw, s::powerlaw_fields(), "powerlaw");
  expect_columns(want.powerlaw->levels, got.powerlaw->levels, s::powerlaw_columns(), "powerlaw");
  EXPECT_EQ(got.diagnosis->number_attributes, want.diagnosis->number_attributes);
  EXPECT_EQ(got.diagnosis->string_attributes, want.diagnosis->string_attributes);

  // The summary reader reads exactly the fields marked for it.
  const io::RecordingResult sum = io::read_summary_results(path);
  ASSERT_EQ(sum.channels.size(), 1u);
  expect_fields(r, sum, s::root_fields(), "/", true);
  expect_fields(want, sum.channels[0], s::channel_fields(), want.path, true);
  ASSERT_TRUE(sum.channels[0].fit && sum.channels[0].psd_fit && sum.channels[0].crosscheck);
  expect_fields(*want.fit, *sum.channels[0].fit, s::fit_fields(), "fit", true);
  expect_fields(*want.crosscheck, *sum.channels[0].crosscheck, s::crosscheck_fields(), "crosscheck",
                true);
  ASSERT_TRUE(sum.channels[0].quality);
  expect_fields(*want.quality, *sum.channels[0].quality, s::quality_fields(), "quality", true);
  ASSERT_TRUE(sum.channels[0].powerlaw);
  expect_fields(*want.powerlaw, *sum.channels[0].powerlaw, s::powerlaw_fields(), "powerlaw", true);
  expect_columns(want.powerlaw->levels, sum.channels[0].powerlaw->levels, s::powerlaw_columns(),
                 "powerlaw");
  EXPECT_TRUE(sum.channels[0].stats.empty());
  EXPECT_FALSE(sum.channels[0].psd || sum.channels[0].diagnosis);
}

// drift/, edits/ and dynamic/ (io/schema_editing.cpp): every line of their tables, and the 2-D
// dynamic/oadev, read back as written; the summary reader reads none of them.
TEST(Schema, EditingTablesRoundTrip) {
  const fs::path path = test::fresh_dir("schema_editing") / "SN_1.allan.h5";
  io::RecordingResult r = every_field();
  io::ChannelResult& ch = r.channels[0];
  io::DriftRecord d;
  d.model = "linear";
  d.fitted_to = "frequency";
  d.parameter = {"offset", "drift"};
  d.value = {1e-9, 3e-15};
  d.sigma = {1e-12, 4e-17};
  d.unit = {"1", "1/s"};
  d.noise_white_pm = 1e-20;
  d.noise_white_fm = 1e-22;
  d.noise_rw_fm = 4e-26;
  d.n_used = 4096;
  d.t = {0.5, 1.5};
  d.residual = {1e-12, -1e-12};
  ch.drift = d;
  ch.edits = {{"excluded", 10, 20, 10.0, 20.0, std::nan(""), std::nan("")},
              {"outlier", 0, 0, 0.0, 0.0, 2e-8, 92.5}};
  ch.dynamic =
      io::DynamicRecord{1024,           256,
                        {1, 2, 4},      {1.0, 2.0, 4.0},
                        {511.5, 767.5}, {1e-11, 7e-12, 5e-12, 1.1e-11, std::nan(""), 5.1e-12}};
  io::write_results(path, r);
  const io::ChannelResult got = io::read_results(path).channels.at(0);
  namespace s = io::schema;
  ASSERT_TRUE(got.drift && got.dynamic);
  expect_fields(*ch.drift, *got.drift, s::drift_fields(), "drift");
  expect_fields(*ch.dynamic, *got.dynamic, s::dynamic_fields(), "dynamic");
  ASSERT_EQ(got.edits.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(got.edits[i].kind, ch.edits[i].kind);
    EXPECT_EQ(got.edits[i].first, ch.edits[i].first);
    EXPECT_EQ(got.edits[i].last, ch.edits[i].last);
    EXPECT_EQ(got.edits[i].t_end, ch.edits[i].t_end);
  }
  EXPECT_EQ(got.edits[1].value, 2e-8);
  EXPECT_EQ(got.edits[1].sigmas, 92.5);
  EXPECT_TRUE(std::isnan(got.edits[0].value));
  ASSERT_EQ(got.dynamic->oadev.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    if (i != 4) {
      EXPECT_EQ(got.dynamic->oadev[i], ch.dynamic->oadev[i]);
    }
  }
  EXPECT_TRUE(std::isnan(got.dynamic->oadev[4]));
  const io::ChannelResult sum = io::read_summary_results(path).channels.at(0);
  EXPECT_FALSE(sum.drift || sum.dynamic);
  EXPECT_TRUE(sum.edits.empty());
}

// A column read when present (upper_datasheet, absent from early files) has no value when
// absent, in both readers: the lot summary shows no bound rather than a zero.
TEST(Schema, AbsentOptionalColumnReadsAsNoValue) {
  const fs::path path = test::fresh_dir("schema_optional") / "SN_1.allan.h5";
  io::RecordingResult r = every_field();
  r.channels[0].diagnosis.reset();
  io::write_results(path, r);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Ldelete(f, "/imu/gyro_x/fit/upper_datasheet", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  io::reseal_file(path);  // as a writer without that column would have sealed it
  for (const io::RecordingResult& back : {io::read_results(path), io::read_summary_results(path)}) {
    ASSERT_TRUE(back.channels.at(0).fit);
    for (const io::TermRecord& t : back.channels[0].fit->terms)
      EXPECT_TRUE(std::isnan(t.upper_datasheet)) << t.term;
    EXPECT_TRUE(std::isnan(io::summary_rows(back).at(0).upper[3]));
  }
}

TEST(Schema, LotSummaryColumnsRoundTrip) {
  const fs::path dir = test::fresh_dir("schema_summary_rt");
  io::SummaryRow row{
      "SN 1", "/imu/gyro_x", "deg/s", 5400000, io::ChannelStatus::failed("why"), "/data/sn1.h5"};
  for (std::size_t i = 0; i < 5; ++i) {
    row.value[i] = 1.5 + static_cast<double>(i);
    row.sigma[i] = 0.1 * static_cast<double>(i + 1);
    row.unit[i] = "u" + std::to_string(i);
    row.detected[i] = 1;
    row.upper[i] = 9.0 + static_cast<double>(i);
    row.spec_term_status[i] = "pass";
    row.h[i] = 1e-22 * static_cast<double>(i + 1);
    row.h_sigma[i] = 1e-23 * static_cast<double>(i + 1);
    row.h_upper[i] = 2e-22 * static_cast<double>(i + 1);
    row.h_detected[i] = 1;
  }
  row.chi2_dof = 1.02;
  row.fit_status = "poor fit (chi2/dof = 1.02)";
  row.readout_n = 18.3;
  row.readout_n_sigma = 0.1;
  row.readout_n_unit = "deg/h/sqrt(Hz)";
  row.readout_n_alt = 0.305;
  row.readout_n_alt_sigma = 0.002;
  row.readout_n_alt_unit = "deg/sqrt(h)";
  row.readout_b = 6.4;
  row.readout_b_sigma = 0.3;
  row.readout_b_unit = "deg/h";
  row.readout_b_tau = 120;
  row.readout_k = 0.5;
  row.readout_k_sigma = 0.05;
  row.readout_k_unit = "deg/h/sqrt(h)";
  row.readout_k_tau = 2000;
  row.readouts_valid = "N B";
  row.max_abs_log10_ratio = 0.03;
  row.crosscheck_worst_tau = 2.5;
  row.fits_agree = 1;
  row.fits_max_abs_z = 0.7;
  row.spec_status = "fail";
  row.spec_detail = "N 18.3 > 18";
  row.outlier = 1;
  row.outlier_terms = "N (z 4.1)";
  row.quality = "saturation;spikes";
  row.n_missing = 11;
  row.n_gap_runs = 2;
  row.n_time_errors = 3;
  row.n_saturated = 40;
  row.longest_run = 41;
  row.n_stuck = 1;
  row.n_spikes = 5;
  row.max_spike_sigmas = 12.5;
  row.unit_spec_status = "fail";
  row.unit_spec_detail = "fail: gyro_x (N)";
  row.lowpass = "auto";
  row.lowpass_cutoff_hz = 29.2;
  row.lowpass_taps = 1.36;
  row.first_tau_fitted = 0.9;
  row.chi2_dof_all_taus = 365.7;
  io::StatisticsRow st{"/imu/gyro_x", "N", "deg/h/sqrt(Hz)", 7, 6, 1, 1.5, 0.2, 1.1, 1.3, 1.7, 1.9,
                       1.0,           2.0};
  io::write_lot_summary(dir, {row}, {st});
  const fs::path h5 = dir / "lot_summary.h5";
  expect_columns({row}, io::read_lot_summary(h5), io::schema::summary_columns(), "/summary");
  expect_columns({st}, io::read_lot_statistics(h5), io::schema::statistics_columns(),
                 "/statistics");
}

// Rewrites the root schema_version of `path` (removing it when `version` is 0).
void set_version(const fs::path& path, std::int64_t version) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Adelete(f, "schema_version");
  if (version > 0) {
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, "schema_version", H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_INT64, &version);
    H5Aclose(a);
    H5Sclose(space);
  }
  H5Fclose(f);
  io::reseal_file(path);  // as that version's writer would have sealed it
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const io::Error& e) {
    return e.what();
  }
  return "";
}

TEST(Schema, VersionWrittenAbsentIsOneNewerIsRefused) {
  const fs::path dir = test::fresh_dir("schema_version");
  const fs::path path = dir / "SN_1.allan.h5";
  io::write_results(path, every_field());
  io::write_lot_summary(dir, io::summary_rows(every_field()));
  const fs::path summary = dir / "lot_summary.h5";
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    std::int64_t v = 0;
    const hid_t a = H5Aopen(f, "schema_version", H5P_DEFAULT);
    ASSERT_GE(a, 0);
    H5Aread(a, H5T_NATIVE_INT64, &v);
    H5Aclose(a);
    H5Fclose(f);
    EXPECT_EQ(v, io::schema::kVersion);
  }
  // Without the attribute: version 1, today's layout, read as before.
  set_version(path, 0);
  set_version(summary, 0);
  EXPECT_EQ(io::read_results(path).channels.size(), 1u);
  EXPECT_EQ(io::read_lot_summary(summary).size(), 1u);
  // A newer version: a clear error naming the file, from every reader.
  set_version(path, io::schema::kVersion + 1);
  set_version(summary, io::schema::kVersion + 1);
  for (const auto& read : std::vector<std::function<void()>>{
           [&] { io::read_results(path); }, [&] { io::read_summary_results(path); }}) {
    const std::string msg = error_of(read);
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("schema_version 2"), std::string::npos) << msg;
  }
  for (const auto& read : std::vector<std::function<void()>>{
           [&] { io::read_lot_summary(summary); }, [&] { io::read_lot_statistics(summary); }}) {
    const std::string msg = error_of(read);
    EXPECT_NE(msg.find(summary.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("schema_version 2"), std::string::npos) << msg;
  }
}

TEST(Status, PrintAndParseBothWays) {
  for (const io::ChannelStatus& s :
       {io::ChannelStatus::ok(), io::ChannelStatus::failed("not an HDF5 file: x"),
        io::ChannelStatus::failed("")})
    EXPECT_EQ(io::parse_channel_status(io::to_string(s), "f.h5", "/c"), s);
  EXPECT_EQ(io::to_string(io::ChannelStatus::ok()), "ok");
  EXPECT_EQ(io::to_string(io::ChannelStatus::failed("too short")), "failed: too short");
  for (const FitStatus s : {FitStatus::Ok, FitStatus::PoorFit, FitStatus::NoData,
                            FitStatus::RankDeficient, FitStatus::NoConvergence}) {
    EXPECT_EQ(io::parse_fit_status(io::to_string(s), "f.h5", "/c/fit"), s);
    EXPECT_EQ(io::to_string(s), kernels::fit_status_name(s));
  }
  EXPECT_EQ(io::to_string(FitStatus::RankDeficient), "rank deficient");
  // Synonyms of the statuses are not statuses.
  for (const char* bad : {"OK", "passed", "failed", "failure: x", ""}) {
    const std::string msg = error_of([&] { io::parse_channel_status(bad, "f.h5", "/c@status"); });
    EXPECT_NE(msg.find("f.h5:/c@status"), std::string::npos) << bad << ": " << msg;
  }
  const std::string msg = error_of([] { io::parse_fit_status("converged", "f.h5", "/c/fit"); });
  EXPECT_NE(msg.find("f.h5:/c/fit"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'converged'"), std::string::npos) << msg;
}

TEST(Status, UnknownStatusInAFileNamesFileAndDataset) {
  const fs::path dir = test::fresh_dir("schema_bad_status");
  const fs::path path = dir / "SN_1.allan.h5";
  io::RecordingResult r = every_field();
  r.channels[0].diagnosis.reset();
  io::write_results(path, r);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t g = H5Gopen2(f, "/imu/gyro_x/fit", H5P_DEFAULT);
    H5Adelete(g, "status");
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(g, "status", t, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* text = "converged";
    H5Awrite(a, t, &text);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(t);
    H5Gclose(g);
    H5Fclose(f);
  }
  io::reseal_file(path);  // a sealed file that holds a status no writer writes
  for (const auto& read : std::vector<std::function<void()>>{
           [&] { io::read_results(path); }, [&] { io::read_summary_results(path); }}) {
    const std::string msg = error_of(read);
    EXPECT_NE(msg.find(path.string() + ":/imu/gyro_x/fit@status"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'converged'"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace allanlot
