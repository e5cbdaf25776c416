// The edits of edit.hpp.
#include "kernels/edit/edit.hpp"

#include "kernels/common/quantile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return quantile_sorted(v, 0.5);
}

// |y - median| / (kMadToSigma * MAD) for every frequency value (NaN for a missing one), or an
// empty vector when the MAD is zero or no value is valid.
std::vector<double> robust_z(const std::vector<double>& y) {
  std::vector<double> valid;
  valid.reserve(y.size());
  for (const double v : y)
    if (!std::isnan(v)) valid.push_back(v);
  if (valid.empty()) return {};
  const double med = median_of(valid);
  for (double& v : valid)
    v = std::abs(v - med);
  const double sigma = kMadToSigma * median_of(std::move(valid));
  if (!(sigma > 0)) return {};
  std::vector<double> z(y.size());
  for (std::size_t i = 0; i < y.size(); ++i)
    z[i] = std::abs(y[i] - med) / sigma;
  return z;
}

}  // namespace

std::string_view to_string(Edit::Kind kind) {
  return kind == Edit::Kind::Outlier ? "outlier" : "excluded";
}

std::vector<Edit> find_outliers(std::span<const double> samples, DataType type, double k) {
  if (!(k > 0) || !std::isfinite(k))
    throw std::invalid_argument("outliers: k = " + std::to_string(k) + " must be finite and > 0");
  const std::size_t n = samples.size();
  std::vector<Edit> edits;
  if (type == DataType::Rate) {
    const std::vector<double> z = robust_z({samples.begin(), samples.end()});
    for (std::size_t i = 0; i < z.size(); ++i)
      if (z[i] > k)
        edits.push_back({Edit::Kind::Outlier, static_cast<std::int64_t>(i),
                         static_cast<std::int64_t>(i), samples[i], z[i]});
    return edits;
  }
  if (n < 3) return edits;
  std::vector<double> y(n - 1);
  for (std::size_t j = 0; j + 1 < n; ++j)
    y[j] = samples[j + 1] - samples[j];
  const std::vector<double> z = robust_z(y);
  if (z.empty()) return edits;
  const auto flagged = [&](std::size_t j) { return z[j] > k; };  // NaN compares false
  for (std::size_t j = 0; j < n; ++j) {
    const bool before = j > 0, after = j + 1 < n;
    if ((before && !flagged(j - 1)) || (after && !flagged(j))) continue;
    const double zj = std::min(before ? z[j - 1] : z[j], after ? z[j] : z[j - 1]);
    edits.push_back({Edit::Kind::Outlier, static_cast<std::int64_t>(j),
                     static_cast<std::int64_t>(j), samples[j], zj});
  }
  return edits;
}

std::vector<Edit> exclusion_edits(std::int64_t n, double rate_hz,
                                  std::span<const TimeRange> ranges) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("exclude: rate_hz must be finite and > 0");
  std::vector<Edit> edits;
  for (const TimeRange& r : ranges) {
    if (!std::isfinite(r.t0_s) || !std::isfinite(r.t1_s) || r.t0_s > r.t1_s)
      throw std::invalid_argument("exclude: range " + std::to_string(r.t0_s) + ":" +
                                  std::to_string(r.t1_s) + " is not T0:T1 with T0 <= T1");
    // Sample k is at k / rate_hz: the first k with k >= t0 rate, the last with k <= t1 rate.
    const double lo = std::max(0.0, std::ceil(r.t0_s * rate_hz));
    const double hi = std::min(static_cast<double>(n - 1), std::floor(r.t1_s * rate_hz));
    if (n == 0 || lo > hi) continue;
    edits.push_back({Edit::Kind::Excluded, static_cast<std::int64_t>(lo),
                     static_cast<std::int64_t>(hi), kNaN, kNaN});
  }
  return edits;
}

void apply_edits(std::span<double> samples, std::span<const Edit> edits) {
  for (const Edit& e : edits)
    for (std::int64_t i = e.first; i <= e.last; ++i)
      samples[static_cast<std::size_t>(i)] = kNaN;
}

}  // namespace allanlot::kernels
