// Data editing before the statistics (docs/editing.md): outliers removed by a robust rule and
// time ranges excluded. An edit never changes a sample's value: it makes the sample missing
// (NaN), and the gap policy (kernels/allan/gaps.hpp) decides what it becomes, as for a sample
// the logger dropped. Every edit is returned with what it removed, so that the results list it.
#pragma once

#include "kernels/allan/phase.hpp"

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Outliers lie more than this many robust sigmas from the median of the frequency: Stable32's
/// default and NIST SP1065's ("Outlier Recognition": |y_i - median| / (MAD / 0.6745) > 5).
inline constexpr double kDefaultOutlierSigmas = 5.0;

/// One edit of a record.
struct Edit {
  enum class Kind { Outlier, Excluded };
  Kind kind = Kind::Outlier;
  std::int64_t first = 0, last = 0;  // sample indices, inclusive
  double value = 0;                  // an outlier: the sample removed; a range: NaN
  double sigmas = 0;                 // an outlier: its distance in robust sigmas; a range: NaN
};

std::string_view to_string(Edit::Kind kind);

/// A time range to exclude, in seconds from the first sample (sample k is at k / rate_hz).
struct TimeRange {
  double t0_s = 0, t1_s = 0;  // t0_s <= t1_s; both ends included
};

/// The outliers of `samples` (NaN = missing, left out) under the robust rule: the frequency
/// values y (the samples for rate data, the phase's first differences for phase data) with
/// |y - median(y)| > k * kMadToSigma * MAD(y). For rate data each such sample is an outlier. For
/// phase data a phase point is one when every frequency value it enters is: x_0 when y_0 is
/// (the first point), x_{n-1} when y_{n-2} is, an interior x_j when both y_{j-1} and y_j are (a
/// single point off moves both of its differences, a step moves one and is no outlier). A MAD
/// of zero (quantized, mostly constant data) flags nothing. Serial, O(N log N) for the median.
/// Precondition (std::invalid_argument): k > 0 and finite.
std::vector<Edit> find_outliers(std::span<const double> samples, DataType type, double k);

/// The edits excluding `ranges` from a record of n samples at rate_hz: one per range that holds
/// at least one sample, in the order given. Preconditions (std::invalid_argument): rate_hz > 0,
/// each range finite with t0_s <= t1_s.
std::vector<Edit> exclusion_edits(std::int64_t n, double rate_hz,
                                  std::span<const TimeRange> ranges);

/// Makes the samples of every edit missing (NaN), in place.
void apply_edits(std::span<double> samples, std::span<const Edit> edits);

}  // namespace allanlot::kernels
