// The data-quality screen of one channel (docs/quality.md): gaps and dropped samples, bad time
// stamps, saturation, stuck output and spikes, counted in a small constant number of cheap
// passes over the samples as read (NaN marks a missing sample), before any statistic is taken.
//
// Every count is a sum, a minimum or a maximum of exact per-chunk quantities merged in index
// order, so the report is the same bits for any thread count (docs/statistics.md "Threads and
// reproducibility").
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace allanlot::kernels {

/// Time-stamp problems found by the reader of a recording with a time column; both zero (and
/// both positions -1) when the recording has no time stamps.
struct TimeStampCounts {
  std::int64_t n_duplicate = 0;       // stamps equal to their predecessor
  std::int64_t first_duplicate = -1;  // sample index of the first, -1 when none
  std::int64_t n_decreasing = 0;      // stamps below their predecessor
  std::int64_t first_decreasing = -1;
};

/// What the screen is given besides the samples.
struct QualityInput {
  std::span<const double> samples;  // physical values, NaN = missing sample
  /// The storage type's limits in physical units (raw min/max * scale + offset, computed as the
  /// reader converts samples) for integer storage; nullopt for floating storage, where only
  /// the record's own extremes can show saturation.
  std::optional<double> storage_min, storage_max;
  TimeStampCounts time;
};

struct QualityOptions {
  int spike_window = 31;         // running-median window, odd, 3..1001 samples
  double spike_sigmas = 10.0;    // a spike departs from the running median by more, > 0
  int saturation_run = 3;        // consecutive samples at an extreme that count as saturation
  double stuck_expected = 1e-6;  // a run is stuck when a clean record expects fewer this long
  int threads = 1;               // as resolve_threads (0 = OpenMP default); results do not vary
};

/// The screen's findings. Positions are sample indices, -1 when there is nothing to point at.
/// "Runs" are maximal runs of consecutive samples with the same value (or all missing).
struct QualityReport {
  std::int64_t n_samples = 0;
  // Gaps: missing samples (NaN) and the runs they form.
  std::int64_t n_missing = 0, n_gap_runs = 0, first_gap = -1;
  // Time stamps, as the reader found them (TimeStampCounts).
  std::int64_t n_duplicate_times = 0, first_duplicate_time = -1;
  std::int64_t n_decreasing_times = 0, first_decreasing_time = -1;
  // Saturation: runs of >= saturation_run samples at a storage limit, or at the record's own
  // minimum or maximum when that value is piled up (more samples there than at the next value
  // inwards, which a natural tail never shows) in a record spanning at least 8 steps.
  std::int64_t n_saturated_runs = 0, n_saturated_samples = 0, first_saturated = -1;
  // Stuck output: the longest run, the shortest run length the quantization statistics make
  // suspicious (stuck_run), and the runs at least that long.
  std::int64_t longest_run = 0, longest_run_start = -1, stuck_run = 0;
  std::int64_t n_stuck_runs = 0, first_stuck = -1;
  double p_equal = 0;     // estimated probability that a sample equals its predecessor
  double p_continue = 0;  // ... given that the predecessor equals its own predecessor
  // Spikes: samples farther than spike_sigmas robust sigmas from the running median, and the
  // largest such distance (in robust sigmas; exact when >= 6, below 6 a lower bound; 0 when
  // nothing could be measured).
  std::int64_t n_spikes = 0, first_spike = -1;
  double max_spike_sigmas = 0;
  std::int64_t spike_window = 0;
  /// The flags raised, "gaps;time_stamps;saturation;stuck;spikes" in that order, "" when none.
  std::string flags;
  friend bool operator==(const QualityReport&, const QualityReport&) = default;
};

/// Screens one channel. Preconditions (std::invalid_argument naming the option): spike_window
/// odd and in 3..1001, spike_sigmas > 0, saturation_run >= 2, stuck_expected in (0, 1).
/// Cost: two O(N) passes over the samples (the running median is taken only where a cheap
/// bound cannot rule out a departure of 6 sigmas; spikes.cpp), about half an overlapping Allan
/// deviation (docs/performance.md); memory: one block of residuals per thread.
QualityReport screen_quality(const QualityInput& in, const QualityOptions& opt = {});

/// The flags of `r` as screen_quality names them (from its counts).
std::string quality_flags(const QualityReport& r);

}  // namespace allanlot::kernels
