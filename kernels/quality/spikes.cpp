// The spike pass of the quality screen (docs/quality.md "Spikes").
//
// Residual r_i = x_i - median of the valid samples in [i - h, i + h] (h = window / 2; the lower
// middle element for an even count). A median of 2h + 1 samples ignores up to h outliers, so a
// burst of up to h spiked samples does not move it, while it follows steps and the slow
// wander of random walk, bias instability and flicker, which a mean or a first difference
// would turn into residuals.
//
// Robust sigma: 1.4826 * median |r| over each block of kBlock samples (1.4826 = 1 / Phi^-1(3/4)
// makes the MAD a consistent estimate of a Gaussian's sigma; Rousseeuw & Croux 1993, JASA 88,
// 1273). Blocks follow a noise level that changes along the record (a vibration test in one
// part of it) and make the pass chunkable.
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
// Cost: the window is kept sorted and one value is exchanged per sample by shifting the
// elements between the old and the new position: O(window) per sample with a small constant,
// no allocation inside a block.
#include "kernels/common/parallel.hpp"
#include "kernels/quality/internal.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace allanlot::kernels::quality_detail {
namespace {

constexpr std::int64_t kBlock = 4096;
constexpr std::int64_t kMinResiduals = 32;  // fewer valid residuals in a block: not judged
constexpr double kMadToSigma = 1.4826;

// A sorted window of the valid samples around the current one.
class Window {
public:
  explicit Window(std::size_t capacity) { v_.reserve(capacity); }
  void insert(double x) { v_.insert(std::upper_bound(v_.begin(), v_.end(), x), x); }
  void erase(double x) { v_.erase(std::lower_bound(v_.begin(), v_.end(), x)); }
  // Replaces one copy of `old_x` by `x`, shifting the elements between the two positions.
  void exchange(double old_x, double x) {
    auto q = static_cast<std::size_t>(std::lower_bound(v_.begin(), v_.end(), old_x) - v_.begin());
    if (x > old_x) {
      for (; q + 1 < v_.size() && v_[q + 1] < x; ++q)
        v_[q] = v_[q + 1];
    } else {
      for (; q > 0 && v_[q - 1] > x; --q)
        v_[q] = v_[q - 1];
    }
    v_[q] = x;
  }
  std::size_t size() const { return v_.size(); }
  double median() const { return v_[(v_.size() - 1) / 2]; }

private:
  std::vector<double> v_;
};

// The median of `a` (valid |r| of one block, >= 1 value, reordered) with the values grouped by
// whole steps and interpolated within the middle group (see above); `step` 0 or infinite: the
// lower middle value itself.
double grouped_median(std::vector<double>& a, double step) {
  const std::size_t k = (a.size() - 1) / 2;
  std::nth_element(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(k), a.end());
  const double m = a[k];
  if (!(step > 0) || !std::isfinite(step)) return m;
  const double group = std::round(m / step);
  std::size_t below = 0, equal = 0;
  for (const double v : a) {
    const double g = std::round(v / step);
    below += g < group ? 1 : 0;
    equal += g == group ? 1 : 0;
  }
  const double lo = group == 0 ? 0.0 : (group - 0.5) * step;
  const double width = group == 0 ? step / 2 : step;
  const double within =
      (static_cast<double>(k) + 0.5 - static_cast<double>(below)) / static_cast<double>(equal);
  return lo + width * within;
}

SpikeStats block_pass(std::span<const double> x, std::int64_t begin, std::int64_t end,
                      std::int64_t h, double sigmas, double step) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const auto at = [&x](std::int64_t i) { return x[static_cast<std::size_t>(i)]; };
  Window w(static_cast<std::size_t>(2 * h + 1));
  for (std::int64_t j = std::max<std::int64_t>(0, begin - h); j < std::min(n, begin + h + 1); ++j)
    if (!std::isnan(at(j))) w.insert(at(j));
  std::vector<double> r(static_cast<std::size_t>(end - begin));
  std::vector<double> abs_r;
  abs_r.reserve(r.size());
  for (std::int64_t i = begin; i < end; ++i) {
    double& ri = r[static_cast<std::size_t>(i - begin)];
    // A median of fewer than h + 1 values (a window mostly in a gap) judges nothing.
    ri = std::isnan(at(i)) || static_cast<std::int64_t>(w.size()) <= h ? NAN : at(i) - w.median();
    if (!std::isnan(ri)) abs_r.push_back(std::abs(ri));
    const std::int64_t out = i - h, in = i + h + 1;
    const bool leaves = out >= 0 && !std::isnan(at(out));
    const bool enters = in < n && !std::isnan(at(in));
    if (leaves && enters)
      w.exchange(at(out), at(in));
    else if (leaves)
      w.erase(at(out));
    else if (enters)
      w.insert(at(in));
  }
  SpikeStats s;
  if (static_cast<std::int64_t>(abs_r.size()) < kMinResiduals) return s;
  const double floor = std::isfinite(step) ? step / std::sqrt(6.0) : 0.0;
  const double sigma = std::max(kMadToSigma * grouped_median(abs_r, step), floor);
  if (!(sigma > 0)) return s;  // a constant block: nothing departs from anything
  for (std::int64_t i = begin; i < end; ++i) {
    const double z = std::abs(r[static_cast<std::size_t>(i - begin)]) / sigma;
    if (std::isnan(z)) continue;
    s.max_sigmas = std::max(s.max_sigmas, z);
    if (z > sigmas) s.spikes.add(1, i);
  }
  return s;
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
