#include "io/time_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace allanlot::io {

namespace {

// The least-squares line through (sample number, stamp), accumulated with Welford's updates of
// the means and co-moments (no cancellation between large sums).
struct LineFit {
  double n = 0, mean_s = 0, mean_t = 0, m2_s = 0, c_st = 0;
  void add(double s, double t) {
    n += 1;
    const double ds = s - mean_s;
    mean_s += ds / n;
    mean_t += (t - mean_t) / n;
    m2_s += ds * (s - mean_s);
    c_st += ds * (t - mean_t);
  }
  double slope() const { return c_st / m2_s; }
};

// The rms of each later stamp's step about its multiple of `step`, the multiple counted in
// medians as the gaps are.
double jitter_rms(const std::vector<double>& times, double median, double step) {
  double sum_sq = 0, latest = times[0];
  std::size_t n_steps = 0;
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double dt = times[i] - latest;
    latest = std::max(latest, times[i]);
    if (!(dt > 0)) continue;
    const double r = dt - std::max(1.0, std::round(dt / median)) * step;
    sum_sq += r * r;
    ++n_steps;
  }
  return n_steps ? std::sqrt(sum_sq / static_cast<double>(n_steps)) : 0.0;
}

}  // namespace

TimeAxis make_time_axis(const std::vector<double>& times, std::int64_t max_missing) {
  TimeAxis axis;
  const std::size_t n = times.size();
  if (n < 2) return axis;
  // Steps from the latest stamp so far; those not positive are out of order, not steps.
  std::vector<double> steps;
  steps.reserve(n - 1);
  double latest = times[0];
  for (std::size_t i = 1; i < n; ++i) {
    if (times[i] > latest) steps.push_back(times[i] - latest);
    latest = std::max(latest, times[i]);
  }
  if (steps.empty()) throw std::invalid_argument("no time stamp is later than the first");
  // The median, not the mean: the missing samples and a few late stamps do not move it.
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  double median = *mid;
  if (steps.size() % 2 == 0) median = (median + *std::max_element(steps.begin(), mid)) / 2;
  steps = {};

  LineFit fit;
  fit.add(0, times[0]);
  std::int64_t pending = 0;  // samples out of order since the latest stamp: they fill its steps
  latest = times[0];
  for (std::size_t i = 1; i < n; ++i) {
    const double dt = times[i] - latest;
    latest = std::max(latest, times[i]);
    const auto sample = static_cast<std::int64_t>(i) + axis.missing;
    if (!(dt > 0)) {  // kept as the next sample, counted
      std::int64_t& count = dt == 0 ? axis.n_duplicate : axis.n_decreasing;
      std::int64_t& first = dt == 0 ? axis.first_duplicate : axis.first_decreasing;
      if (count++ == 0) first = sample;
      ++pending;
      continue;
    }
    const double steps_spanned = std::max(1.0, std::round(dt / median));
    const double k = std::max(1.0, steps_spanned - static_cast<double>(pending));
    pending = 0;
    if (k > static_cast<double>(max_missing - axis.missing + 1))
      throw std::invalid_argument("the time step before row " + std::to_string(i + 1) + " is " +
                                  std::to_string(k) +
                                  " sample steps: more missing samples than the file has rows");
    if (k >= 2) {
      const auto count = static_cast<std::int64_t>(k) - 1;
      axis.gaps.emplace_back(i, count);
      axis.missing += count;
    }
    fit.add(static_cast<double>(static_cast<std::int64_t>(i) + axis.missing), times[i]);
  }
  axis.step = fit.slope();
  axis.jitter_rms = jitter_rms(times, median, axis.step);
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

std::string exact_text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

void add_time_axis_facts(std::vector<std::pair<std::string, std::string>>& facts,
                         const TimeAxis& axis, double unit_s) {
  facts.emplace_back("time_step_s", exact_text(axis.step * unit_s));
  facts.emplace_back("time_missing_samples", std::to_string(axis.missing));
  facts.emplace_back("time_jitter_rms_s", exact_text(axis.jitter_rms * unit_s));
}

}  // namespace allanlot::io
