#include "kernels/allan/gaps.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

namespace allanlot::kernels {
namespace {

[[noreturn]] void bad_policy(std::string_view text) {
  throw std::invalid_argument("gap policy '" + std::string(text) +
                              "' is not one of skip, fill, fill:N (N >= 1 samples)");
}

// The line through the first and last valid points, per sample: the slope phase data are
// continued along at the record's ends. 0 when fewer than two points are valid.
double mean_slope(std::span<const double> x) {
  std::size_t first = 0, last = x.size();
  while (first < x.size() && std::isnan(x[first]))
    ++first;
  while (last > first && std::isnan(x[last - 1]))
    --last;
  if (last - first < 2) return 0.0;
  return (x[last - 1] - x[first]) / static_cast<double>(last - 1 - first);
}

// Fills samples a .. b-1 (all NaN) from their valid neighbours, at a - 1 and b when inside.
void fill_run(std::span<double> v, std::size_t a, std::size_t b, DataType type, double slope) {
  const bool left = a > 0, right = b < v.size();
  if (left && right) {
    // Linear interpolation between v[a-1] and v[b]: the estimate of every missing sample from
    // its two neighbours, for rate and phase alike.
    const double y0 = v[a - 1], y1 = v[b];
    const double span = static_cast<double>(b - a + 1);
    for (std::size_t k = a; k < b; ++k)
      v[k] = y0 + (y1 - y0) * (static_cast<double>(k - a + 1) / span);
    return;
  }
  const double step = type == DataType::Phase ? slope : 0.0;
  if (left) {
    for (std::size_t k = a; k < b; ++k)
      v[k] = v[a - 1] + step * static_cast<double>(k - a + 1);
  } else {
    for (std::size_t k = a; k < b; ++k)
      v[k] = v[b] - step * static_cast<double>(b - k);
  }
}

}  // namespace

GapPolicy parse_gap_policy(std::string_view text) {
  GapPolicy p;
  if (text == "skip") {
    p.mode = GapPolicy::Mode::Skip;
    p.max_run = 0;
    return p;
  }
  if (text == "fill") {
    p.max_run = 0;
    return p;
  }
  constexpr std::string_view prefix = "fill:";
  if (text.substr(0, prefix.size()) != prefix) bad_policy(text);
  const std::string_view num = text.substr(prefix.size());
  std::int64_t n = 0;
  const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), n);
  if (num.empty() || ec != std::errc() || end != num.data() + num.size() || n < 1) bad_policy(text);
  p.max_run = n;
  return p;
}

std::string to_string(const GapPolicy& policy) {
  if (policy.mode == GapPolicy::Mode::Skip) return "skip";
  return policy.max_run == 0 ? "fill" : "fill:" + std::to_string(policy.max_run);
}

GapFill fill_gaps(std::span<double> samples, DataType type, const GapPolicy& policy) {
  GapFill out;
  const bool fill = policy.mode == GapPolicy::Mode::Fill;
  double slope = 0.0;
  bool slope_known = false;
  const std::size_t n = samples.size();
  for (std::size_t a = 0; a < n;) {
    if (!std::isnan(samples[a])) {
      ++a;
      continue;
    }
    std::size_t b = a;
    while (b < n && std::isnan(samples[b]))
      ++b;
    const auto len = static_cast<std::int64_t>(b - a);
    ++out.runs;
    out.missing += len;
    const bool whole = a == 0 && b == n;
    if (fill && !whole && (policy.max_run == 0 || len <= policy.max_run)) {
      if (!slope_known && type == DataType::Phase && (a == 0 || b == n)) {
        slope = mean_slope(samples);
        slope_known = true;
      }
      fill_run(samples, a, b, type, slope);
      ++out.filled_runs;
      out.filled += len;
    } else {
      ++out.runs_left;
      out.missing_left += len;
    }
    a = b;
  }
  return out;
}

PhaseData make_phase(std::span<double> samples, DataType type, double rate_hz,
                     const GapPolicy& policy, GapFill* fill, int nthreads) {
  const GapFill f = fill_gaps(samples, type, policy);
  PhaseData p = make_phase(std::span<const double>(samples), type, rate_hz, nthreads);
  p.n_filled = f.filled;
  if (fill) *fill = f;
  return p;
}

}  // namespace allanlot::kernels
