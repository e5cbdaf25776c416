// The Allan variance a model's bias jumps add over a finite record (kernels/simulate/step.hpp
// step_avar_sampled, plus_steps_avar): each jump's second differences in closed form, and those
// of jumps close together summed window by window.
#include "kernels/simulate/step.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::kernels {

namespace {

// sum_{k=k1}^{k2} (a - k)^2 in closed form, from b = a - k1 (no cancellation between the large
// k and a): sum_{j=0}^{c-1} (b - j)^2 = c b^2 - b c (c - 1) + (c - 1) c (2c - 1) / 6.
double sum_sq_to(double a, std::int64_t k1, std::int64_t k2) {
  if (k2 < k1) return 0.0;
  const double b = a - static_cast<double>(k1), c = static_cast<double>(k2 - k1 + 1);
  return c * b * b - b * c * (c - 1) + (c - 1) * c * (2 * c - 1) / 6;
}

}  // namespace

double step_avar_sampled(const Step& step, double rate_hz, std::int64_t m, std::int64_t n_samples) {
  if (m < 1 || n_samples < 2 * m)
    throw std::invalid_argument("step_avar_sampled: need 1 <= m and 2 m <= n_samples, got m = " +
                                std::to_string(m) + ", n_samples = " + std::to_string(n_samples));
  const double s = step.time_s * rate_hz, md = static_cast<double>(m);
  // Windows k with 0 < s - k < 2 m, inside 0 .. n - 2m; rising where s - k <= m.
  const std::int64_t k_lo =
      std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor(s - 2 * md)) + 1);
  const std::int64_t k_hi =
      std::min<std::int64_t>(n_samples - 2 * m, static_cast<std::int64_t>(std::ceil(s)) - 1);
  if (k_hi < k_lo) return 0.0;
  const auto k_rise = std::max<std::int64_t>(k_lo, static_cast<std::int64_t>(std::ceil(s - md)));
  const double rise = sum_sq_to(s, k_rise, k_hi);
  const double fall = sum_sq_to(s - 2 * md, k_lo, std::min(k_hi, k_rise - 1));
  return step.size * step.size * (rise + fall) /
         (md * md * 2.0 * static_cast<double>(n_samples - 2 * m + 1));
}

namespace {

// The second difference of the windows' means at window k that a jump of unit size at s samples
// gives: the triangle of step_avar_sampled, (s - k) / m rising over 0 < s - k <= m, then
// (2m - (s - k)) / m falling to 2m.
double step_difference(double s, std::int64_t k, std::int64_t m) {
  const double u = s - static_cast<double>(k), md = static_cast<double>(m);
  if (!(u > 0.0) || !(u < 2.0 * md)) return 0.0;
  return (u <= md ? u : 2.0 * md - u) / md;
}

// Jumps whose windows overlap (two within 2 m samples of each other): their second differences
// add before they are squared, so the variance has their cross terms (two opposite jumps close
// together, a bias excursion, give far less than the sum of their shares). Summed over every
// window that any jump reaches, NIST SP1065 eq. (11) as step_avar_sampled.
double joint_steps_avar(std::span<const Step> steps, double rate_hz, std::int64_t m,
                        std::int64_t n_samples) {
  std::vector<std::pair<std::int64_t, std::int64_t>> ranges;
  for (const Step& st : steps) {
    const double s = st.time_s * rate_hz;
    const std::int64_t lo = std::max<std::int64_t>(
        0, static_cast<std::int64_t>(std::floor(s - 2.0 * static_cast<double>(m))) + 1);
    const std::int64_t hi =
        std::min<std::int64_t>(n_samples - 2 * m, static_cast<std::int64_t>(std::ceil(s)) - 1);
    if (lo <= hi) ranges.emplace_back(lo, hi);
  }
  std::sort(ranges.begin(), ranges.end());
  double sum = 0.0;
  std::int64_t next = 0;  // the first window not yet summed
  for (const auto& [lo, hi] : ranges)
    for (std::int64_t k = std::max(lo, next); k <= hi; ++k) {
      double d = 0.0;
      for (const Step& st : steps)
        d += st.size * step_difference(st.time_s * rate_hz, k, m);
      sum += d * d;
      next = k + 1;
    }
  return sum / (2.0 * static_cast<double>(n_samples - 2 * m + 1));
}

// True when two of the jumps are within 2 m samples of each other.
bool steps_overlap(std::span<const Step> steps, double rate_hz, std::int64_t m) {
  for (std::size_t a = 0; a < steps.size(); ++a)
    for (std::size_t b = a + 1; b < steps.size(); ++b)
      if (std::abs(steps[a].time_s - steps[b].time_s) * rate_hz < 2.0 * static_cast<double>(m))
        return true;
  return false;
}

}  // namespace

double plus_steps_avar(double avar, std::span<const Step> steps, double rate_hz, std::int64_t m,
                       std::int64_t n_samples) {
  if (steps_overlap(steps, rate_hz, m)) {
    if (m < 1 || n_samples < 2 * m)
      throw std::invalid_argument("plus_steps_avar: need 1 <= m and 2 m <= n_samples");
    return avar + joint_steps_avar(steps, rate_hz, m, n_samples);
  }
  for (const Step& st : steps)
    avar += step_avar_sampled(st, rate_hz, m, n_samples);
  return avar;
}

}  // namespace allanlot::kernels
