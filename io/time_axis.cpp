#include "io/time_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::io {

TimeAxis make_time_axis(const std::vector<double>& times, std::int64_t max_missing) {
  TimeAxis axis;
  const std::size_t n = times.size();
  if (n < 2) return axis;
  std::vector<double> steps(n - 1);
  for (std::size_t i = 1; i < n; ++i)
    steps[i - 1] = times[i] - times[i - 1];
  // The median, not the mean: the missing samples and a few late stamps do not move it.
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  axis.step = *mid;
  if (steps.size() % 2 == 0) axis.step = (axis.step + *std::max_element(steps.begin(), mid)) / 2;
  steps = {};

  double sum_sq = 0;
  for (std::size_t i = 1; i < n; ++i) {
    const double dt = times[i] - times[i - 1];
    const double k = std::max(1.0, std::round(dt / axis.step));
    if (k > static_cast<double>(max_missing - axis.missing + 1))
      throw std::invalid_argument("the time step before row " + std::to_string(i + 1) + " is " +
                                  std::to_string(k) +
                                  " sample steps: more missing samples than the file has rows");
    if (k >= 2) {
      const auto count = static_cast<std::int64_t>(k) - 1;
      axis.gaps.emplace_back(i, count);
      axis.missing += count;
    }
    const double r = dt - k * axis.step;
    sum_sq += r * r;
  }
  axis.jitter_rms = std::sqrt(sum_sq / static_cast<double>(n - 1));
  return axis;
}

std::vector<double> with_gaps(std::vector<double> values, const TimeAxis& axis) {
  if (axis.missing == 0) return values;
  std::vector<double> out;
  out.reserve(values.size() + static_cast<std::size_t>(axis.missing));
  std::size_t from = 0;
  for (const auto& [row, count] : axis.gaps) {
    out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(from),
               values.begin() + static_cast<std::ptrdiff_t>(row));
    out.insert(out.end(), static_cast<std::size_t>(count),
               std::numeric_limits<double>::quiet_NaN());
    from = row;
  }
  out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(from), values.end());
  return out;
}

}  // namespace allanlot::io
