// Results files (docs/formats.md "Results file layout") and the lot summary ("Lot summary"): the
// records in memory and their readers and writers. What each group and column holds is described
// once, in io/schema.hpp.
#pragma once

#include "io/diagnosis.hpp"
#include "io/editing.hpp"
#include "io/status.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/quality/quality.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// One term of the equation (3) fit, in channel units and in datasheet units.
struct TermRecord {
  std::string term;             // "R", "K", "B", "N", "Q"
  double value = 0, sigma = 0;  // channel units and seconds (docs/formats.md)
  double upper = 0;             // one-sided 95 % upper bound (meaningful when not detected)
  bool detected = false;        // significantly non-zero
  std::string unit;             // e.g. "deg/s*s^0.5"
  double value_datasheet = 0, sigma_datasheet = 0, upper_datasheet = 0;
  std::string unit_datasheet;      // e.g. "deg/h/sqrt(Hz)"
  double value_datasheet_alt = 0;  // the secondary datasheet form, where there is one
  std::string unit_datasheet_alt;  // e.g. "deg/sqrt(h)"; "" when none
};

/// A conventional read-out of the curve (IEEE Std 952 annex C) beside the fit.
struct ReadoutRecord {
  std::string name;  // "N_1s", "bias_instability", "K_3s"
  bool valid = false;
  double value = 0, sigma = 0, tau_s = 0, model = 0;  // channel units; model: same on the fit
  double value_datasheet = 0, sigma_datasheet = 0;
  std::string unit_datasheet;
  // The other datasheet form where there is one (N at 1 s as ARW deg/sqrt(h) or VRW
  // m/s/sqrt(h)); NaN and "" otherwise.
  double value_datasheet_alt = std::numeric_limits<double>::quiet_NaN();
  double sigma_datasheet_alt = std::numeric_limits<double>::quiet_NaN();
  std::string unit_datasheet_alt;
};

/// One parameter of an effect outside eq. (3) in fit/'s model (fit/effects/, docs/formats.md):
/// one row per parameter, the effects in the order they were named.
struct EffectRecord {
  std::int64_t effect_index = 0;  // 0, 1, ...: its effect, named or added on the curve
  std::string effect;             // the effect's name (kernels::effect_name)
  std::string parameter;          // its key in the model file: "frequency_hz", "q", "sigma", ...
  double value = 0, sigma = 0;    // sigma NaN when not estimable
  std::int64_t bound = 0;         // 0 estimate; -1 at the search's lower end, +1 upper end
};

/// The fit/ (or psd_fit/) group.
struct FitRecord {
  std::string method;
  kernels::FitStatus status = kernels::FitStatus::NoData;  // Ok, or why there is no fit
  int rank = 0;
  double chi2_dof = 0;
  std::vector<TermRecord> terms;
  std::vector<double> tau, adev_model;  // fit/: the model on the oadev taus
  std::vector<ReadoutRecord> readouts;
  // psd_fit/ only: the log-binned PSD frequencies fitted and the fitted model's expected Welch
  // value there (u^2/Hz), and the term-by-term comparison with fit/ (kernels::compare_fits):
  // z per term, its largest |z|, the term where it is reached, and agree (1 agree, 0 not,
  // -1 not compared).
  std::vector<double> f, psd_model;
  std::vector<double> z_vs_fit;
  double max_abs_z = std::numeric_limits<double>::quiet_NaN();
  std::string worst_term;
  int agree = -1;
  // fit/ only: the sensor's filter and the taus it leaves the fit (docs/fit-and-psd.md "The
  // sensor's filter"): lowpass "auto" (found on the curve), "option" (--lowpass) or "none";
  // its cutoff_hz or taps (NaN for the other form and without a filter); the auto test's
  // criterion (NaN when not tested); the first tau and the number of taus the fit used; the
  // chi2/dof of the fit over all taus, for comparison with chi2_dof.
  std::string lowpass;
  double lowpass_cutoff_hz = std::numeric_limits<double>::quiet_NaN();
  double lowpass_taps = std::numeric_limits<double>::quiet_NaN();
  double lowpass_delta_ic = std::numeric_limits<double>::quiet_NaN();
  double first_tau_fitted = std::numeric_limits<double>::quiet_NaN();
  std::int64_t taus_fitted = 0;
  double chi2_dof_all_taus = std::numeric_limits<double>::quiet_NaN();
  // fit/ only, when eq. (3) alone is a poor fit and analyze modelled the channel as diagnose
  // does (docs/fit-and-psd.md "When eq. (3) is a poor fit"): terms, adev_model and the
  // read-outs' model are then the model's; `model` says it in words ("eq. (3) + lowpass 1.15
  // taps, resonance 17.2 Hz"; "" when the terms are eq. (3)'s own fit); its gap against the
  // measured curve and the p95 of its Monte Carlo replicas' gaps; model_within_noise 1 within
  // noise, 0 not, -1 not modelled; the effects' parameters. status and chi2_dof stay those of
  // eq. (3) alone.
  std::string model;
  double model_gap = std::numeric_limits<double>::quiet_NaN();
  double model_gap_p95 = std::numeric_limits<double>::quiet_NaN();
  int model_replicas = 0;
  int model_within_noise = -1;
  std::vector<EffectRecord> effects;
};

/// The fit's status as people read it: "ok", "poor fit (chi2/dof = 5974)" (the model misses
/// part of the curve: `allanlot diagnose` names what), "rank deficient", ...; a modelled poor
/// fit adds the model: "poor fit (chi2/dof = 709); modelled: eq. (3) + lowpass 1.15 taps,
/// resonance 0.567 Hz (within noise)".
std::string fit_status_text(const FitRecord& f);

/// The psd/ group: the Welch PSD, log-binned for compact storage and plots.
struct PsdRecord {
  std::string method;  // e.g. "welch hann 50% overlap, L=131072, 81 segments"
  std::string convention = "one-sided";
  std::vector<double> f, psd, edf;  // Hz, u^2/Hz (one-sided), chi-square dof of each value
  std::vector<std::int64_t> n_avg;  // Welch bins averaged into each value
};

/// The crosscheck/ group: equation (2) applied to the measured PSD against the overlapping
/// Allan variance, tau by tau.
struct CrosscheckRecord {
  std::vector<double> tau, avar_time, avar_psd, ratio;
  std::vector<std::uint8_t> valid;      // 1 where eq. (2) on the PSD is trustworthy
  double max_abs_log10_ratio = 0;       // over the valid taus (NaN when none)
  std::vector<double> valid_tau_range;  // {min, max} of the valid taus
  double worst_tau = std::numeric_limits<double>::quiet_NaN();  // where |log10 ratio| peaks
};

/// One level h_alpha of a clock's power-law model (powerlaw/, docs/clocks.md): S_y(f) =
/// h_alpha f^alpha of the fractional frequency, in Hz^(-1-alpha).
struct PowerLawLevelRecord {
  std::int64_t alpha = 0;     // 2, 1, 0, -1, -2
  std::string name;           // kernels::powerlaw::noise_type_name(alpha), e.g. "white FM"
  double h = 0, h_sigma = 0;  // the fitted level and its standard uncertainty
  double h_upper = 0;         // one-sided 95 % upper bound (the number to read when not detected)
  bool detected = false;      // significantly above zero
};

/// The powerlaw/ group: the levels fitted to OADEV and MDEV (kernels/powerlaw/fit.hpp) and the
/// model's deviations on the taus fitted.
struct PowerLawRecord {
  std::string method;
  std::string status;  // ok, no_data, rank_deficient, no_convergence
  std::vector<PowerLawLevelRecord> levels;
  std::vector<double> tau, adev_model, mdev_tau, mdev_model;
};

/// Everything written for one channel.
struct ChannelResult {
  std::string path;  // the channel's own path, e.g. "/imu/gyro_x"
  std::string units;
  double sample_rate_hz = 0.0;
  std::int64_t n_samples = 0;
  std::int64_t n_gaps = 0;
  std::string data_type = "rate";  // "rate" or "phase"
  // What the gap policy (analyze --gaps, kernels/allan/gaps.hpp) did; written when n_gaps > 0.
  std::string gap_policy;          // "skip", "fill" or "fill:N"
  std::int64_t n_filled = 0;       // missing samples filled by interpolation
  std::int64_t filled_runs = 0;    // runs of missing samples filled
  std::int64_t gap_runs_left = 0;  // runs left as gaps (terms touching them left out)
  // The samples as analysed (after scale and offset; gaps left out), as Stable32 heads its
  // tables: largest, smallest and mean. NaN when not known (files of earlier versions).
  double data_max = std::numeric_limits<double>::quiet_NaN();
  double data_min = std::numeric_limits<double>::quiet_NaN();
  double data_mean = std::numeric_limits<double>::quiet_NaN();
  ChannelStatus status;  // ok, or failed and why
  std::string notes;     // what was not computed and why, e.g. a skipped statistic
  /// (statistic name, result) in the order computed; written to allan/<name>/.
  std::vector<std::pair<std::string, kernels::StatResult>> stats;
  std::optional<FitRecord> fit;                   // fit/: the equation (3) fit of the oadev curve
  std::optional<FitRecord> psd_fit;               // psd_fit/: the same five terms from the PSD
  std::optional<PsdRecord> psd;                   // psd/
  std::optional<CrosscheckRecord> crosscheck;     // crosscheck/
  std::optional<kernels::QualityReport> quality;  // quality/: the data-quality screen
  std::optional<DiagnosisRecord> diagnosis;       // diagnosis/, added by `allanlot diagnose -o`
  std::optional<PowerLawRecord> powerlaw;         // powerlaw/: a clock's power-law levels

  // Data editing and the dynamic deviation (io/editing.hpp, analyze --drift, --outliers,
  // --exclude, --dynamic): absent unless asked for.
  std::optional<DriftRecord> drift;      // drift/
  std::vector<EditRecord> edits;         // edits/, written when not empty
  std::optional<DynamicRecord> dynamic;  // dynamic/
};

/// One results file: one input recording.
struct RecordingResult {
  std::string device_id;  // as found in the input (sanitized only for the file name)
  std::string source_file;
  std::string tool_version;
  std::string created_utc;
  std::string command_line;
  /// Further root attributes: analysis options, thread count, git revision (read back:
  /// `statistic` and `taus`).
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<ChannelResult> channels;
};

/// Writes `r` to `path` through a temporary file renamed into place: the results file is
/// complete or absent. Throws io::Error naming the path on failure.
void write_results(const std::filesystem::path& path, const RecordingResult& r);

/// Reads a results file back: every group of the schema (io/schema.hpp). io::Error naming the
/// file for a schema_version newer than this build reads, or an unknown status.
RecordingResult read_results(const std::filesystem::path& path);

/// One row of the lot summary: one (device, channel), or one failed input (channel empty).
struct SummaryRow {
  std::string device_id;
  std::string channel;
  std::string units;
  std::int64_t n_samples = 0;
  ChannelStatus status;
  std::string source_file;
  /// The five fitted terms R, K, B, N, Q in datasheet units (NaN when there is no fit).
  std::array<double, 5> value{nan(), nan(), nan(), nan(), nan()};
  std::array<double, 5> sigma{nan(), nan(), nan(), nan(), nan()};
  std::array<std::string, 5> unit;
  std::array<std::uint8_t, 5> detected{};
  double chi2_dof = nan();
  std::string fit_status;  // fit_status_text of fit/; "" without a fit
  // Whether the terms come from a curve described within its noise (docs/fit-and-psd.md): 1
  // eq. (3) fits (status ok) or the poor fit's model is within noise, 0 a poor fit whose model
  // is not within noise (or that was not modelled), -1 no fit or not known (a row read back
  // from a lot summary file: not a column, fit_status says it in words). The spec never passes
  // or fails a term on 0.
  std::int8_t fit_within_noise = -1;
  // The read-outs of fit/readouts (IEEE Std 952 annex C) in datasheet units, given whether or
  // not the fit detects their term (readouts_valid names the terms it detects): N at 1 s (and
  // its ARW/VRW form), bias instability (min deviation / 0.664) and K at 3 s, each with its
  // uncertainty and, for B and K, the tau it was read at. NaN without a fit.
  double readout_n = nan(), readout_n_sigma = nan();
  std::string readout_n_unit;
  double readout_n_alt = nan(), readout_n_alt_sigma = nan();
  std::string readout_n_alt_unit;
  double readout_b = nan(), readout_b_sigma = nan(), readout_b_tau = nan();
  std::string readout_b_unit;
  double readout_k = nan(), readout_k_sigma = nan(), readout_k_tau = nan();
  std::string readout_k_unit;
  std::string readouts_valid;           // e.g. "N B": the read-outs whose term the fit detects
  double max_abs_log10_ratio = nan();   // the eq. (2) cross-check (crosscheck/)
  double crosscheck_worst_tau = nan();  // the tau where |log10 ratio| is largest [s]
  // Allan fit (fit/) against PSD fit (psd_fit/): 1 the five terms agree within their
  // uncertainties, 0 they do not, -1 not compared; and the largest |z| of the comparison.
  std::int8_t fits_agree = -1;
  double fits_max_abs_z = nan();
  /// One-sided 95 % upper bound of each term in datasheet units (fit/upper_datasheet): what a
  /// datasheet quotes for a term the fit does not detect.
  std::array<double, 5> upper{nan(), nan(), nan(), nan(), nan()};
  // Pass/fail against a spec file (src/spec.hpp): "pass", "fail", "undecided", "no spec" (no
  // rule matches the channel), "no data" (failed input or channel, or no fit); "" when no spec
  // was given. spec_detail: the terms that decided it, e.g. "N 18.3±0.04 > 18 deg/h/sqrt(Hz)".
  std::string spec_status;
  std::string spec_detail;
  // 1 when a term of this unit lies more than 3.5 robust spreads from the lot median of its
  // channel (src/lot_summary.hpp); outlier_terms says which, with the modified z-scores.
  std::uint8_t outlier = 0;
  std::string outlier_terms;
  /// The decision of each term R, K, B, N, Q that the spec limits ("pass", "fail", "undecided");
  /// "" for a term without a limit or without a spec.
  std::array<std::string, 5> spec_term_status;
  /// The data-quality screen (quality/, docs/quality.md): the flags raised ("gaps;saturation",
  /// "ok" when none; "" when the channel was not screened: a failed input, an older file), and
  /// the counts an engineer checks first (0 and NaN when not screened).
  std::string quality;
  std::int64_t n_missing = 0;      // missing samples
  std::int64_t n_gap_runs = 0;     // runs of them
  std::int64_t n_time_errors = 0;  // duplicate or decreasing time stamps
  std::int64_t n_saturated = 0;    // samples in saturated runs
  std::int64_t longest_run = 0;    // longest run of identical samples
  std::int64_t n_stuck = 0;        // runs long enough to be stuck output
  std::int64_t n_spikes = 0;
  double max_spike_sigmas = nan();  // largest distance from the running median, robust sigmas
  // The verdict of the whole unit (device_id) against the spec, the same on each of its rows
  // (src/lot/spec.hpp judge_units): "pass" only when every channel a rule covers passes, else
  // "fail", "undecided", "no data" or "no spec"; "" without a spec. unit_spec_detail names the
  // channels behind it, e.g. "fail: gyro_x (N); undecided: accel_z".
  std::string unit_spec_status;
  std::string unit_spec_detail;
  // The sensor's filter in the eq. (3) fit (fit/, docs/fit-and-psd.md "The sensor's filter"):
  // fit/lowpass ("auto", "auto-unused", "option", "none"; "" without a fit), its cutoff or taps
  // (NaN for the other form), the first tau the fit used and the chi2/dof over every tau.
  std::string lowpass;
  double lowpass_cutoff_hz = nan(), lowpass_taps = nan();
  double first_tau_fitted = nan();
  double chi2_dof_all_taus = nan();
  // A clock's power-law levels (powerlaw/, docs/clocks.md), alpha 2, 1, 0, -1, -2 (columns h2,
  // h1, h0, hm1, hm2): h_alpha, its sigma, upper bound and detection; NaN without the model.
  std::array<double, 5> h{nan(), nan(), nan(), nan(), nan()};
  std::array<double, 5> h_sigma{nan(), nan(), nan(), nan(), nan()};
  std::array<double, 5> h_upper{nan(), nan(), nan(), nan(), nan()};
  std::array<std::uint8_t, 5> h_detected{};

  SummaryRow() = default;
  SummaryRow(std::string device, std::string chan, std::string u, std::int64_t n, ChannelStatus st,
             std::string source)
      : device_id(std::move(device)), channel(std::move(chan)), units(std::move(u)), n_samples(n),
        status(std::move(st)), source_file(std::move(source)) {}

private:
  static constexpr double nan() { return std::numeric_limits<double>::quiet_NaN(); }
};

/// Lot statistics of one term of one channel kind (the same channel path across units), in
/// datasheet units, over the units whose channel has a fitted value (src/lot_summary.hpp).
struct StatisticsRow {
  std::string channel;          // channel path, e.g. "/imu/gyro_x"
  std::string term;             // "R", "K", "B", "N", "Q"
  std::string unit;             // datasheet unit of every value in the row
  std::int64_t n = 0;           // units with a value
  std::int64_t n_detected = 0;  // of those, units where the fit detects the term
  std::int64_t n_outliers = 0;  // units flagged as outliers on this term
  double median = std::numeric_limits<double>::quiet_NaN();
  double spread = std::numeric_limits<double>::quiet_NaN();  // 1.4826 * MAD
  double p5 = std::numeric_limits<double>::quiet_NaN();
  double p25 = std::numeric_limits<double>::quiet_NaN();
  double p75 = std::numeric_limits<double>::quiet_NaN();
  double p95 = std::numeric_limits<double>::quiet_NaN();
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

/// A CSV field (RFC 4180): as it is, or in double quotes with inner quotes doubled when it
/// holds a comma, a quote or a line break; bytes that are not UTF-8 as `\xNN` (io/utf8.hpp).
/// A field a spreadsheet would take for a formula (first character =, +, -, @, tab or CR, and
/// not a number such as -1.5e-3) gets a single quote first and is quoted (docs/formats.md).
std::string csv_field(const std::string& text);

/// A CSV number with `digits` significant digits ("%.*g"); empty for NaN, as pandas and
/// spreadsheets read a missing value.
std::string csv_number(double v, int digits);

/// The files of the lot summary in `outdir`: lot_summary.csv, lot_statistics.csv and
/// lot_summary.h5 (what write_lot_summary writes).
std::array<std::filesystem::path, 3> lot_summary_files(const std::filesystem::path& outdir);

/// Writes OUTDIR/lot_summary.csv, OUTDIR/lot_statistics.csv and OUTDIR/lot_summary.h5
/// (compound datasets /summary and /statistics; `attributes` become string attributes of the
/// file's root, e.g. the spec file used, beside schema_version), each file atomically. The
/// columns are io/schema.hpp's summary_columns() and statistics_columns().
void write_lot_summary(const std::filesystem::path& outdir, const std::vector<SummaryRow>& rows,
                       const std::vector<StatisticsRow>& statistics = {},
                       const std::vector<std::pair<std::string, std::string>>& attributes = {});

/// Reads the /summary compound dataset of a lot_summary.h5. Columns missing from older files
/// keep their defaults (NaN, "", 0, -1 for fits_agree). io::Error naming the file for a newer
/// schema_version or an unknown status.
std::vector<SummaryRow> read_lot_summary(const std::filesystem::path& h5_path);

/// Reads the /statistics compound dataset of a lot_summary.h5 (empty when the file predates it).
std::vector<StatisticsRow> read_lot_statistics(const std::filesystem::path& h5_path);

/// The summary rows of one recording's results.
std::vector<SummaryRow> summary_rows(const RecordingResult& r);

/// Reads only what summary_rows needs: the fields io/schema.hpp marks `summary` (root and
/// channel attributes, the datasheet columns and attributes of fit/ and psd_fit/, the
/// attributes of crosscheck/); allan/, psd/, diagnosis/ and every per-tau or per-frequency array
/// are never opened, so a lot of thousands of units is summarized quickly.
/// summary_rows(read_summary_results(p)) == summary_rows(read_results(p)).
RecordingResult read_summary_results(const std::filesystem::path& path);

}  // namespace allanlot::io
