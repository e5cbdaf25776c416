// Phase (integrated rate) samples prepared once per channel for the prefix-sum Allan kernels.
//
// Every Allan-family statistic of SP1065 is a sum of squared finite differences of the phase
// x_k = tau0 * sum_{j<k} y_j. Building x once, as a prefix sum of the rate y, turns each
// tau's window sums into differences of two array elements (O(N) per tau, independent of m).
#pragma once

#include "kernels/common/large_vector.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// What the samples of a channel are (docs/formats.md "Units and conventions").
enum class DataType {
  Rate,  // frequency-like: angular rate, acceleration, fractional frequency
  Phase  // its integral: angle, velocity, time error
};

/// Phase points of one channel, with the mean rate removed and gaps recorded.
///
/// The mean rate is removed before integration because a large mean (an accelerometer's
/// 1 g) would otherwise dominate x and differences of nearby x would lose digits; a
/// constant rate is a linear phase, which every second (and higher) difference cancels, so
/// no statistic changes (SP1065 sec. 5.2: the Allan family is insensitive to frequency
/// offset). The sums are accumulated in long double in fixed-size chunks combined in index
/// order, so x is bit-identical for any thread count.
struct PhaseData {
  /// Phase points x_0 .. x_N (N+1 points for N rate samples), in u*s for rate input (u = the
  /// channel's units) and in the input's own units for phase input.
  LargeVector<double> x;
  /// Empty when the channel has no gap. Otherwise gaps[k] is the number of missing
  /// increments (rate samples) before phase point k, so a term that uses x_a .. x_b is
  /// valid exactly when gaps[b] == gaps[a].
  std::vector<std::int64_t> gaps;
  double tau0_s = 1.0;      // sample interval
  std::int64_t n_gaps = 0;  // missing samples in the input (NaN)
  /// Samples filled by interpolation before x was built (gaps.hpp): estimates that carry no
  /// information of their own, which the intervals count (confidence.hpp stat_edf). 0 = none.
  std::int64_t n_filled = 0;
  /// With filled samples: `gaps` as if they were still missing (the record as `skip` sees it),
  /// for the rows where leaving their terms out costs little (gaps.hpp). Empty otherwise.
  std::vector<std::int64_t> skip_gaps;
  double mean_rate = 0.0;  // the removed mean rate, in u (rate input) or phase units per s

  std::int64_t n_points() const { return static_cast<std::int64_t>(x.size()); }
  bool has_gaps() const { return !gaps.empty(); }
  /// True when no increment between phase points a <= b is missing.
  bool clean(std::int64_t a, std::int64_t b) const {
    return gaps.empty() || gaps[static_cast<std::size_t>(b)] == gaps[static_cast<std::size_t>(a)];
  }
};

/// Builds phase points from rate samples y_0 .. y_{N-1} taken at `rate_hz`:
/// x_0 = 0, x_{k+1} = x_k + (y_k - ybar) / rate_hz, with ybar the mean of the valid samples.
/// NaN samples are gaps (their increment is recorded as missing and counted as zero).
/// Preconditions (std::invalid_argument naming the parameter): rate_hz finite and > 0,
/// at least 2 samples, at least one valid sample, no infinite sample.
PhaseData phase_from_rate(std::span<const double> rate, double rate_hz, int nthreads = 0);

/// Builds phase points from phase samples x_0 .. x_{N-1}: the increments x_{k+1} - x_k are
/// treated as rate samples (scaled by rate_hz) and integrated again, which removes the
/// linear phase trend without changing any statistic. A NaN phase point makes both of its
/// increments missing. Preconditions as for phase_from_rate, with at least 3 samples.
PhaseData phase_from_phase(std::span<const double> phase, double rate_hz, int nthreads = 0);

/// Dispatches on the data type.
PhaseData make_phase(std::span<const double> samples, DataType type, double rate_hz,
                     int nthreads = 0);

}  // namespace allanlot::kernels
