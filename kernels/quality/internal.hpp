// Private to kernels/quality/: the per-chunk tallies of the run pass (runs.cpp) and the spike
// pass (spikes.cpp), and how tallies of neighbouring chunks merge. Every merge is exact (sums of
// integers, minima, maxima), so any split of the record into chunks gives the same result.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <span>

namespace allanlot::kernels::quality_detail {

/// How many runs of some kind, and where the first one starts (-1: none yet).
struct Tally {
  std::int64_t count = 0, first = -1;
  void add(std::int64_t n, std::int64_t at) {
    count += n;
    if (at >= 0 && (first < 0 || at < first)) first = at;
  }
  void add(const Tally& o) { add(o.count, o.first); }
};

/// One value among the record's extremes: how many samples hold it, and its runs of at least
/// the saturation length (count, first start, samples in them).
struct Extreme {
  bool set = false;
  double value = 0;
  std::int64_t samples = 0;
  Tally long_runs;
  std::int64_t long_run_samples = 0;
};

/// Run-length histogram: lengths below kShortRuns in an array, longer ones (rare) in a map.
inline constexpr std::int64_t kShortRuns = 64;
struct RunHistogram {
  std::array<Tally, kShortRuns> shorts{};
  std::map<std::int64_t, Tally> longs;
  void add(std::int64_t length, std::int64_t start) {
    if (length < kShortRuns)
      shorts[static_cast<std::size_t>(length)].add(1, start);
    else
      longs[length].add(1, start);
  }
  void add(const RunHistogram& o) {
    for (std::size_t i = 0; i < shorts.size(); ++i)
      shorts[i].add(o.shorts[i]);
    for (const auto& [len, t] : o.longs)
      longs[len].add(t);
  }
};

/// Everything the run pass learns from one chunk (the runs that start in it).
struct RunStats {
  std::int64_t n_missing = 0;
  Tally gap_runs;
  std::int64_t n_pairs = 0;  // consecutive pairs of valid samples
  RunHistogram valid_runs;   // runs of equal valid samples, by length (length 1 included)
  Tally at_storage_limit;    // runs of >= the saturation length at a storage limit
  std::int64_t at_storage_limit_samples = 0;
  std::array<Extreme, 2> high{}, low{};  // the two largest and the two smallest distinct values
  double min_step = std::numeric_limits<double>::infinity();  // smallest nonzero |x[i+1]-x[i]|
  void merge(const RunStats& later);
};

struct RunPassOptions {
  std::int64_t saturation_run = 3;
  bool has_min = false, has_max = false;
  double storage_min = 0, storage_max = 0;
};

/// The run pass over x, chunked over `threads` threads.
RunStats run_pass(std::span<const double> x, const RunPassOptions& opt, int threads);

/// The runs of at least `min_length` equal valid samples whose value is none of `except`, in
/// one sequential walk (run only when the histogram shows such runs at all).
Tally long_runs_except(std::span<const double> x, std::int64_t min_length,
                       std::span<const double> except);

/// What the spike pass finds.
struct SpikeStats {
  Tally spikes;
  double max_sigmas = 0;
};

/// The spike pass: |x[i] - running median| > sigmas * robust sigma, with the robust sigma of
/// each block of samples floored at the quantization step's share (spikes.cpp).
SpikeStats spike_pass(std::span<const double> x, int window, double sigmas, double step,
                      int threads);

}  // namespace allanlot::kernels::quality_detail
