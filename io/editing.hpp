// What data editing and the dynamic deviation leave in a channel's results (docs/formats.md
// "Results file layout", docs/editing.md): the fitted drift (drift/), the edits (edits/) and the
// dynamic Allan deviation (dynamic/). Their tables are io/schema.hpp's (drift_fields,
// edit_columns, dynamic_fields); dynamic/oadev, a 2-D dataset, is written here.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace allanlot::io {

/// drift/: the drift model fitted and removed before the statistics.
struct DriftRecord {
  std::string model;                   // linear, quadratic, log, diffusion
  std::string fitted_to;               // frequency or phase
  std::vector<std::string> parameter;  // e.g. offset, drift
  std::vector<double> value, sigma;    // estimates and standard uncertainties
  std::vector<std::string> unit;       // of each value, e.g. "1/s", "s/s^2"
  // The noise model behind sigma, per sample: white PM (phase^2), white FM and random-walk FM
  // increments (rate^2).
  double noise_white_pm = 0, noise_white_fm = 0, noise_rw_fm = 0;
  std::int64_t n_used = 0;  // samples fitted
  // The residuals against the whole model for the report's plot: block means of at most 512
  // blocks, at the blocks' centres (s from the first sample).
  std::vector<double> t, residual;
};

/// One row of edits/: a sample (or range) made missing before the statistics.
struct EditRecord {
  std::string kind;                                          // outlier or excluded
  std::int64_t first = 0, last = 0;                          // sample indices, inclusive
  double t_start = 0, t_end = 0;                             // s from the first sample
  double value = std::numeric_limits<double>::quiet_NaN();   // an outlier's sample
  double sigmas = std::numeric_limits<double>::quiet_NaN();  // its robust distance
};

/// dynamic/: the overlapping Allan deviation of a sliding window.
struct DynamicRecord {
  std::int64_t window = 0, step = 0;  // samples
  std::vector<std::int64_t> m;        // averaging factors
  std::vector<double> tau;            // s
  std::vector<double> t_center;       // s, each window's centre
  std::vector<double> oadev;          // [window index x tau], row-major; NaN: no value
};

}  // namespace allanlot::io
