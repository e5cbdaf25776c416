// The spike pass of the quality screen (docs/quality.md "Spikes").
//
// Residual r_i = x_i - median of the valid samples in [i - h, i + h] (h = window / 2; the lower
// middle element for an even count). A median of 2h + 1 samples ignores up to h outliers, so a
// burst of up to h spiked samples does not move it, while it follows steps and the slow
// wander of random walk, bias instability and flicker, which a mean or a first difference
// would turn into residuals. A spike is |r_i| > sigmas * sigma.
//
// Robust sigma: 1.4826 * median |x - m| over each block of kBlock samples, m the median of the
// sample's sub-block of kSub consecutive samples, taken on every kSigmaStride-th sub-block (1024
// residuals a block: the MAD's relative error is then about 4 %) (1.4826 = 1 / Phi^-1(3/4) makes
// the MAD a consistent estimate of a Gaussian's sigma; Rousseeuw & Croux 1993, JASA 88, 1273). The
// sub-block medians stand in for the running median here because the scale needs every
// residual and a running median at every sample costs twice an overlapping Allan deviation;
// for noise they are the same kind of residual, and near a step or in fast wander they are
// larger, which errs towards fewer spikes. Blocks follow a noise level that changes along the
// record (a vibration test in one part of it) and make the pass chunkable.
//
// Quantized data. When the noise is about one quantization step, |r| takes a handful of values
// (0, 1, 2 steps) and its plain median jumps between them: from one block to the next the MAD
// is 0 or a whole step, and the threshold with it (seen on ADIS16405 accelerometers, steps of
// 3.33 mg). The median is therefore taken as if each |r| were spread uniformly over its step
// (over [k - 1/2, k + 1/2] steps, [0, 1/2] for 0), i.e. interpolated within the group of equal
// values that holds it, as grouped-data medians are; for unquantized data every group holds one
// value and this is the plain median. The sigma is floored at step / sqrt(6), the standard
// deviation of the difference of two values each rounded to the step (each rounding error
// uniform, variance step^2 / 12), so that a clean one-step flicker is never a spike.
//
// Cost. The running median is computed only where it can matter: the window of every sample of
// a sub-block lies within the sub-blocks up to ceil(h / kSub) away, so its median lies between
// their minimum and maximum, and |r_i| <= max(x_i - min, max - x_i). Only samples where this
// bound exceeds kExact sigmas (under 0.1 % of clean noise) get their window's median exactly
// (a selection over 2h + 1 values); the others provably have |r_i| below it. Spikes and every
// departure of kExact sigmas or more are therefore exact; max_sigmas is exact when it is at
// least kExact.
#include "kernels/common/parallel.hpp"
#include "kernels/common/quantile.hpp"
#include "kernels/quality/internal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace allanlot::kernels::quality_detail {
namespace {

constexpr std::int64_t kBlock = 4096;
constexpr std::int64_t kSub = 32;
constexpr std::int64_t kMinResiduals = 32;  // fewer valid residuals in a block: not judged
constexpr std::int64_t kSigmaStride = 4;
constexpr double kExact = 6.0;

// The lower middle of a[0, n), 1 <= n <= kSub, by ranks: a[i] is it when at most k values are
// below it and more than k are at or below it (k = (n - 1) / 2). The comparisons run two at a
// time without branches over the values padded with NaN (which is neither below nor at or
// below anything), where a selection over 32 values is branch-bound (the sub-block medians of
// block_sigma were a third of the screen's time); the value is the same.
double small_median(const double* a, std::int64_t n) {
  using D2 = double __attribute__((vector_size(16)));
  using L2 = std::int64_t __attribute__((vector_size(16)));
  constexpr int kPairs = static_cast<int>(kSub / 2);
  D2 v[kPairs];
  for (int p = 0; p < kPairs; ++p)
    for (int l = 0; l < 2; ++l)
      v[p][l] = 2 * p + l < n ? a[2 * p + l] : NAN;
  const std::int64_t k = (n - 1) / 2;
  for (std::int64_t i = 0;; ++i) {
    const D2 ai = D2{} + a[i];
    L2 below{}, at_or_below{};
    for (int p = 0; p < kPairs; ++p) {
      below -= v[p] < ai;  // a true comparison is all ones, i.e. -1
      at_or_below -= v[p] <= ai;
    }
    if (below[0] + below[1] <= k && k < at_or_below[0] + at_or_below[1]) return a[i];
  }
}

// The lower middle of the valid values of x[lo, hi) (reordering `buf`), or NaN when fewer than
// `need` are valid.
double window_median(std::span<const double> x, std::int64_t lo, std::int64_t hi, std::size_t need,
                     std::vector<double>& buf) {
  // Every value is written and only a valid one kept (no branch on the data).
  buf.resize(static_cast<std::size_t>(hi - lo));
  std::size_t valid = 0;
  for (std::int64_t j = lo; j < hi; ++j) {
    const double v = x[static_cast<std::size_t>(j)];
    buf[valid] = v;
    valid += std::isnan(v) ? 0 : 1;
  }
  buf.resize(valid);
  if (buf.size() < need || buf.empty()) return NAN;
  if (buf.size() <= static_cast<std::size_t>(kSub))
    return small_median(buf.data(), static_cast<std::int64_t>(buf.size()));
  const auto mid = buf.begin() + static_cast<std::ptrdiff_t>((buf.size() - 1) / 2);
  std::nth_element(buf.begin(), mid, buf.end());
  return *mid;
}

// The smallest and largest valid value of x[lo, hi): std::min(a, b) is (b < a) ? b : a, so a
// NaN b leaves a. Four accumulators each, so that the loop is not one chain of min latencies.
std::pair<double, double> min_max(std::span<const double> x, std::int64_t lo, std::int64_t hi) {
  std::array<double, 4> mn{INFINITY, INFINITY, INFINITY, INFINITY};
  std::array<double, 4> mx{-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  const double* p = x.data();
  std::int64_t j = lo;
  for (; j + 4 <= hi; j += 4)
    for (std::size_t k = 0; k < 4; ++k) {
      mn[k] = std::min(mn[k], p[j + static_cast<std::int64_t>(k)]);
      mx[k] = std::max(mx[k], p[j + static_cast<std::int64_t>(k)]);
    }
  for (; j < hi; ++j) {
    mn[0] = std::min(mn[0], p[j]);
    mx[0] = std::max(mx[0], p[j]);
  }
  return {std::min(std::min(mn[0], mn[1]), std::min(mn[2], mn[3])),
          std::max(std::max(mx[0], mx[1]), std::max(mx[2], mx[3]))};
}

// Every sample's window x[i - h, i + h] lies within its sub-block's neighbourhood: the
// sub-blocks (of kSub samples, numbered from sample 0) `reach` = ceil(h / kSub) on each side.
// Their minima and maxima bound the window medians of a whole sub-block.
struct Bracket {
  std::int64_t first = 0;  // index of the first sub-block held
  std::vector<double> lo, hi;
};

Bracket sub_block_extremes(std::span<const double> x, std::int64_t begin, std::int64_t end,
                           std::int64_t reach) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const std::int64_t n_sub = (n + kSub - 1) / kSub;
  Bracket b;
  b.first = std::max<std::int64_t>(0, begin / kSub - reach);
  const std::int64_t last = std::min(n_sub, (end + kSub - 1) / kSub + reach);
  for (std::int64_t j = b.first; j < last; ++j) {
    const auto [mn, mx] = min_max(x, j * kSub, std::min(n, (j + 1) * kSub));
    b.lo.push_back(mn);
    b.hi.push_back(mx);
  }
  return b;
}

// The median of `a` (valid |r| of one block, >= 1 value, reordered) with the values grouped by
// whole steps and interpolated within the middle group (see above); `step` 0 or infinite: the
// lower middle value itself.
double grouped_median(std::vector<double>& a, double step) {
  const std::size_t k = (a.size() - 1) / 2;
  std::nth_element(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(k), a.end());
  const double m = a[k];
  // Beyond 1e12 steps the data are not quantized in any sense that matters (and whole steps
  // would overflow the integer groups).
  if (!(step > 0) || !std::isfinite(step) || !(m / step < 1e12)) return m;
  const auto group_of = [step](double v) {
    const double q = v / step + 0.5;  // v >= 0: truncation rounds to the nearest step
    return q < 2e12 ? static_cast<std::int64_t>(q) : std::int64_t{2'000'000'000'000};
  };
  const std::int64_t group = group_of(m);
  std::size_t below = 0, equal = 0;
  for (const double v : a) {
    const std::int64_t g = group_of(v);
    below += g < group ? 1 : 0;
    equal += g == group ? 1 : 0;
  }
  const double lo = group == 0 ? 0.0 : (static_cast<double>(group) - 0.5) * step;
  const double width = group == 0 ? step / 2 : step;
  const double within =
      (static_cast<double>(k) + 0.5 - static_cast<double>(below)) / static_cast<double>(equal);
  return lo + width * within;
}

// The block's robust sigma (0 when it has too few valid samples to judge).
double block_sigma(std::span<const double> x, std::int64_t begin, std::int64_t end, double step,
                   std::vector<double>& buf) {
  std::vector<double> abs_r;
  abs_r.reserve(static_cast<std::size_t>(end - begin));
  for (std::int64_t s = begin; s < end; s += kSigmaStride * kSub) {
    const std::int64_t e = std::min(end, s + kSub);
    const double m = window_median(x, s, e, 1, buf);
    if (std::isnan(m)) continue;
    for (std::int64_t i = s; i < e; ++i)
      if (!std::isnan(x[static_cast<std::size_t>(i)]))
        abs_r.push_back(std::abs(x[static_cast<std::size_t>(i)] - m));
  }
  if (static_cast<std::int64_t>(abs_r.size()) < kMinResiduals) return 0;
  const double floor = std::isfinite(step) ? step / std::sqrt(6.0) : 0.0;
  return std::max(kMadToSigma * grouped_median(abs_r, step), floor);
}

SpikeStats block_pass(std::span<const double> x, std::int64_t begin, std::int64_t end,
                      std::int64_t h, double sigmas, double step) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const auto at = [&x](std::int64_t i) { return x[static_cast<std::size_t>(i)]; };
  std::vector<double> buf;
  buf.reserve(static_cast<std::size_t>(2 * h + 1 + kSub));
  SpikeStats st;
  const double sigma = block_sigma(x, begin, end, step, buf);
  if (!(sigma > 0)) return st;  // too few samples, or a constant block: nothing departs
  const double bound = std::min(kExact, sigmas) * sigma;
  const std::int64_t reach = (h + kSub - 1) / kSub;
  const Bracket br = sub_block_extremes(x, begin, end, reach);
  const auto held = static_cast<std::int64_t>(br.lo.size());
  for (std::int64_t s = begin; s < end; s += kSub) {
    const std::int64_t e = std::min(end, s + kSub);
    double lo = INFINITY, hi = -INFINITY;
    for (std::int64_t j = std::max<std::int64_t>(0, s / kSub - reach - br.first);
         j <= std::min(held - 1, (e - 1) / kSub + reach - br.first); ++j) {
      lo = std::min(lo, br.lo[static_cast<std::size_t>(j)]);
      hi = std::max(hi, br.hi[static_cast<std::size_t>(j)]);
    }
    for (std::int64_t i = s; i < e; ++i) {
      const double v = at(i);
      if (std::isnan(v) || !(v - lo > bound || hi - v > bound)) continue;
      // A median of fewer than h + 1 values (a window mostly in a gap) judges nothing.
      const double m = window_median(x, std::max<std::int64_t>(0, i - h), std::min(n, i + h + 1),
                                     static_cast<std::size_t>(h + 1), buf);
      if (std::isnan(m)) continue;
      const double z = std::abs(v - m) / sigma;
      st.max_sigmas = std::max(st.max_sigmas, z);
      if (z > sigmas) st.spikes.add(1, i);
    }
  }
  return st;
}

}  // namespace

SpikeStats spike_pass(std::span<const double> x, int window, double sigmas, double step,
                      int threads) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  // Blocks of kBlock samples, the last one taking the remainder (kBlock to 2 kBlock - 1
  // samples), so that no block's sigma rests on a handful of residuals.
  const std::int64_t nb = std::max<std::int64_t>(1, n / kBlock);
  std::vector<SpikeStats> parts(static_cast<std::size_t>(nb));
  const int nt = resolve_threads(threads);
  ExceptionCollector errors;
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t b = 0; b < nb; ++b)
    errors.run([&] {
      const std::int64_t e = b + 1 == nb ? n : (b + 1) * kBlock;
      parts[static_cast<std::size_t>(b)] = block_pass(x, b * kBlock, e, window / 2, sigmas, step);
    });
  errors.rethrow();
  SpikeStats all;
  for (const SpikeStats& p : parts) {
    all.spikes.add(p.spikes);
    all.max_sigmas = std::max(all.max_sigmas, p.max_sigmas);
  }
  return all;
}

}  // namespace allanlot::kernels::quality_detail
