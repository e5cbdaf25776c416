// What the HTML report reads beside read_results(): groups and columns that other commands
// add to the results layout (`psd_fit/`, `diagnosis/`, lot-summary columns such as
// `fits_agree` and `spec_status`). Their exact form may still change, so everything here is
// read defensively: an absent group or column is simply absent, a group that does not have
// the expected shape gives a note (shown in the report) instead of an error.
#pragma once

#include "io/results.hpp"

#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// A `/<channel>/diagnosis` group as written by `allanlot diagnose -o OUT.h5` (docs/diagnose.md
/// "Output"; io/diagnosis.hpp writes it), read for display only. Curves are kept
/// here as Allan *deviations*: datasets named `adev_*` are taken as they are, all others are
/// variances and converted by a square root.
///
/// Dataset names looked for (first found wins; the first name is what diagnose writes):
///   tau:             tau, tau_s
///   measured:        avar_measured, adev_measured
///   model before:    avar_model_before, adev_model_before
///   model after:     avar_model_after, adev_model_after
///   MC band (after): mc_after_lo/mc_after_hi, avar_mc_lo/avar_mc_hi, mc_lo/mc_hi,
///                    mc_band_lo/mc_band_hi, adev_mc_lo/adev_mc_hi
///   MC band before:  mc_before_lo/mc_before_hi
///   edf:             edf
///   effects:         effect, effects_named, effects (strings; or a string attribute
///                    effects_named, a JSON list or a comma-separated list)
///   per iteration:   gap_iteration_before, gap_iteration_after (or gap, gap_per_iteration,
///                    gaps), delta_ic, parameters (JSON strings)
///   gaps:            attributes gap_before, gap_after (else the first and last iteration's)
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
  double gap_before = nan(), gap_after = nan();
  /// Every attribute of the group, as text (numbers with 6 significant digits; arrays joined
  /// by ", "), in name order: the models, the parameters and anything else diagnose records.
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<std::string> notes;  // datasets present but unusable, and why
};

/// The optional groups of one HDF5 file (a results file, or a diagnose output).
struct ReportExtras {
  std::string device_id;  // root attribute `device_id` ("" when absent)
  /// `<channel>/psd_fit` groups (the PSD-domain eq. (3) fit, same datasets as fit/), keyed by
  /// channel path. Missing datasets are left empty / NaN.
  std::vector<std::pair<std::string, FitRecord>> psd_fits;
  std::vector<DiagnosisView> diagnoses;  // every group named `diagnosis`, in path order
  std::vector<std::string> notes;        // groups that could not be read, and why
};

/// Reads the optional groups of `file`. Throws io::Error (naming the file) only when the file
/// cannot be opened as HDF5; anything unexpected inside becomes a note.
ReportExtras read_report_extras(const std::filesystem::path& file);

/// The columns of a lot summary's `/summary` compound dataset, read by name, whatever members
/// it has: strings as they are, numbers as text with up to 10 significant digits ("" for NaN).
struct SummaryColumns {
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> values;  // values[column][row]
  std::size_t rows = 0;
  /// Index of the column named `name`, or -1.
  int find(const std::string& name) const;
};

/// Reads every string or numeric member of `/summary` in `h5_path` (members of other types
/// are left out). Throws io::Error naming the file when it cannot be read.
SummaryColumns read_summary_columns(const std::filesystem::path& h5_path);

}  // namespace allanlot::io
