// What the HTML report reads beside read_results(): the psd_fit/ and diagnosis/ groups of the
// results (docs/formats.md "Results file layout"), the diagnosis groups of a diagnose output,
// and the lot summary's columns by name. Everything comes from the typed readers of the schema
// (io/schema.hpp), which check schema_version; nothing here reads HDF5 itself.
#pragma once

#include "io/diagnosis.hpp"
#include "io/results.hpp"

#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// A diagnosis/ group (io::DiagnosisRecord, docs/diagnose.md "Output") prepared for display:
/// the curves as Allan *deviations* (square roots of the stored variances).
struct DiagnosisView {
  static constexpr double nan() { return std::numeric_limits<double>::quiet_NaN(); }
  std::string channel;  // the channel path, e.g. "/imu/gyro_x"
  std::vector<double> tau;
  std::vector<double> measured, model_before, model_after;  // deviations
  std::vector<double> band_lo, band_hi;                     // MC band of the model after
  std::vector<double> band_before_lo, band_before_hi;       // MC band of the model before
  std::vector<double> edf;
  std::vector<std::string> effects_named;  // in the order they were added
  std::vector<double> iteration_gap_before, iteration_gap_after, iteration_delta_ic;
  std::vector<std::string> iteration_parameters;  // JSON per iteration
  /// The gap_before and gap_after attributes, else the first and last iteration's.
  double gap_before = nan(), gap_after = nan();
  /// diagnose's verdict (attribute gap_within_noise: 1 within, 0 beyond; -1 when absent), the
  /// p95 of the corrected model's replicas' gaps it was judged by, and their number.
  int within_noise = -1;
  double gap_noise_p95 = nan();
  int replicas = 0;
  /// Every attribute of the group, as text (numbers with 6 significant digits), in name order:
  /// the models, the parameters and anything else diagnose records.
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<std::string> notes;  // curves present but not drawable, and why
};

/// The display form of a diagnosis record.
DiagnosisView diagnosis_view(const DiagnosisRecord& d);

/// The optional groups of one HDF5 file (a results file, or a diagnose output).
struct ReportExtras {
  std::string device_id;  // root attribute `device_id` ("" when absent)
  /// `<channel>/psd_fit` groups with terms (the PSD-domain eq. (3) fit), keyed by channel path.
  std::vector<std::pair<std::string, FitRecord>> psd_fits;
  std::vector<DiagnosisView> diagnoses;  // every diagnosis group, in path order
  std::vector<std::string> notes;        // what could not be shown, and why
};

/// The extras of a results file already read with read_results.
ReportExtras report_extras(const RecordingResult& r);

/// Reads the extras of `file`: its root attributes and channels (read_results) and every
/// diagnosis group in it (read_diagnoses). Throws io::Error naming the file when it is not
/// HDF5, has a newer schema_version, or holds a group of the wrong shape.
ReportExtras read_report_extras(const std::filesystem::path& file);

/// The columns of a lot summary's `/summary` (read_lot_summary), by name: strings as they are,
/// numbers as text with up to 10 significant digits ("" for NaN). Columns an older file lacks
/// hold their defaults.
struct SummaryColumns {
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> values;  // values[column][row]
  std::size_t rows = 0;
  /// Index of the column named `name`, or -1.
  int find(const std::string& name) const;
};

/// Reads `/summary` of `h5_path` through read_lot_summary. Throws io::Error naming the file
/// when it cannot be read.
SummaryColumns read_summary_columns(const std::filesystem::path& h5_path);

}  // namespace allanlot::io
