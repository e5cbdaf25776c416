// The time column of a text recording (docs/formats.md "Text recordings"): a step of about k
// median steps is k - 1 missing samples; the sample step is then the least-squares slope of
// the stamps over their sample numbers (the mean rate of the clock, whose error falls as
// N^-1.5 with jitter, where the median of jittered steps is off by about its spread / sqrt(N));
// the scatter of the steps about their multiples of it is the timing jitter.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

struct TimeAxis {
  double step = 0.0;  // the fitted sample step, in the time column's units
  /// (row, count): `count` missing samples before row `row` (0-based, row > 0), in order.
  std::vector<std::pair<std::size_t, std::int64_t>> gaps;
  std::int64_t missing = 0;  // sum of the counts
  double jitter_rms = 0.0;   // rms of (step - k * median step), in the time column's units
  // Stamps not after the latest before them (a logger's repeated record or a clock set back):
  // each is kept as the next sample and counted for the data-quality screen (sample indices of
  // the record with its gaps; -1 when none); the step to the next later stamp counts them
  // among the samples it spans, so that they make no gap.
  std::int64_t n_duplicate = 0, first_duplicate = -1;
  std::int64_t n_decreasing = 0, first_decreasing = -1;
};

/// From the times of the rows (at least two). Steps are taken from the latest stamp so far, so
/// that one stamp out of order is counted (TimeAxis::n_decreasing) and does not make a gap
/// after it. Throws std::invalid_argument when the steps would ask for more missing samples
/// than `max_missing` (a time stamp far off the others), or when no step is positive.
TimeAxis make_time_axis(const std::vector<double>& times, std::int64_t max_missing);

/// `values` (one per row) with NaN inserted where the axis has missing samples.
std::vector<double> with_gaps(std::vector<double> values, const TimeAxis& axis);

/// A number as a recording's facts store it: 17 significant digits, so that it reads back exact.
std::string exact_text(double v);

/// The facts every recording with a time axis records (docs/formats.md): time_step_s,
/// time_missing_samples and time_jitter_rms_s; `unit_s` is the axis's unit in seconds.
void add_time_axis_facts(std::vector<std::pair<std::string, std::string>>& facts,
                         const TimeAxis& axis, double unit_s);

}  // namespace allanlot::io
