// The time column of a text recording (docs/formats.md "Text recordings"): the sample step is
// the median of the time steps; a step of about k medians is k - 1 missing samples; the
// scatter of the steps about their multiples of the median is the timing jitter.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace allanlot::io {

struct TimeAxis {
  double step = 0.0;  // median step, in the time column's units
  /// (row, count): `count` missing samples before row `row` (0-based, row > 0), in order.
  std::vector<std::pair<std::size_t, std::int64_t>> gaps;
  std::int64_t missing = 0;  // sum of the counts
  double jitter_rms = 0.0;   // rms of (step - k * median step), in the time column's units
};

/// From strictly increasing times (at least two). Throws std::invalid_argument when the steps
/// would ask for more missing samples than `max_missing` (a time stamp far off the others).
TimeAxis make_time_axis(const std::vector<double>& times, std::int64_t max_missing);

/// `values` (one per row) with NaN inserted where the axis has missing samples.
std::vector<double> with_gaps(std::vector<double> values, const TimeAxis& axis);

}  // namespace allanlot::io
