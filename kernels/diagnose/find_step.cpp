// The time-domain witness of a bias jump (docs/diagnose.md "A bias jump"): the
// change-point test that names `step`, as the periodogram's line names `sinusoid`.
//
// At scale m the second differences of the phase, D_k = (x_{k+2m} - 2 x_{k+m} + x_k) / m (the
// differences of adjacent m-sample means whose mean square is twice the overlapping Allan
// variance, NIST SP1065 eq. (11)), carry a jump of size d at sample s as a triangle peaking at
// d at k = s - m, and any power-law noise, flicker and random walk included, as a Gaussian
// variate of mean zero (a ramp adds a constant, removed with the mean). The test is the largest
// |D_k - mean| over the record against the root mean square of the others (the windows within
// 2 m of the largest left out, so the jump does not inflate its own yardstick): a Student t
// whose degrees of freedom are those of that mean square, an Allan variance estimate, at their
// smallest over the power laws (Greenhall & Riley's edf, kernels/uncertainty/edf.hpp), so never
// overstated. The largest of the windows' t is judged by Pickands' tail of the maximum of a
// Gaussian sequence with correlation 1 - C l near lag 0 (Pickands 1969, Trans. AMS 145):
// P(max > u) ~ (1 + C W u^2) P(|t| > u) over W windows, with C the correlation's slope near
// zero measured on the windows (3 / 2m for white FM; about 1 for white PM, whose D are
// uncorrelated, where the count becomes every window; see scan_scale), at most W P(|t| > u),
// Bonferroni over the scales. The record-wide false alarm is then
// about `false_alarm` or less for any Gaussian noise of stationary increments, with no model
// needed. A spike (one outlier) also makes a large D, but a plateau: D = -D_max on one side m
// windows away, where a jump's triangle is back at zero; a candidate whose D at k +- m has the
// opposite sign at half its size or more is a spike, not a jump. A short burst (a knock on the
// sensor: a few samples of both signs) makes a large D at small m that halves at each doubling
// of m, where a jump's stays: a candidate that keeps less than half its size at 2 m or 4 m is
// not a jump either (the real ADIS16405 imu4 record has one, 1 s long, at 4046 s).
#include "kernels/diagnose/diagnose.hpp"

#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

// One scale's largest excursion of D from its mean.
struct ScaleScan {
  std::int64_t m = 0;
  std::int64_t k = -1;  // window of the largest |D - mean|
  double d = 0.0;       // D_k - mean (signed)
  double mean = 0.0, rms = 0.0;
  double p = 1.0;      // Bonferroni over the scale's windows
  bool spike = false;  // a spike or a short burst, not a jump
};

double second_difference(const std::vector<double>& x, std::int64_t k, std::int64_t m) {
  const auto u = static_cast<std::size_t>(k), um = static_cast<std::size_t>(m);
  return (x[u + 2 * um] - 2.0 * x[u + um] + x[u]) / static_cast<double>(m);
}

constexpr FiniteDifferenceKind kOverlappingAllan{2, true, false};

ScaleScan scan_scale(const std::vector<double>& x, std::int64_t n, std::int64_t m) {
  ScaleScan s;
  s.m = m;
  const std::int64_t windows = n - 2 * m + 1;
  double sum = 0.0;
  for (std::int64_t k = 0; k < windows; ++k)
    sum += second_difference(x, k, m);
  const double mean_all = sum / static_cast<double>(windows);
  double best = -1.0;
  for (std::int64_t k = 0; k < windows; ++k) {
    const double a = std::abs(second_difference(x, k, m) - mean_all);
    if (a > best) {
      best = a;
      s.k = k;
    }
  }
  // Mean, mean square and the products at lags 1 and L = m / 4 of the windows away from the
  // largest.
  const std::int64_t lag = std::max<std::int64_t>(1, m / 4);
  double s1 = 0.0, s2 = 0.0, s11 = 0.0, s1l = 0.0;
  std::int64_t count = 0, pairs = 0, pairs_l = 0;
  const auto away = [&](std::int64_t k) { return std::abs(k - s.k) >= 2 * m; };
  for (std::int64_t k = 0; k < windows; ++k) {
    if (!away(k)) continue;
    const double v = second_difference(x, k, m) - mean_all;
    s1 += v;
    s2 += v * v;
    ++count;
    if (k >= 1 && away(k - 1)) {
      s11 += v * (second_difference(x, k - 1, m) - mean_all);
      ++pairs;
    }
    if (k >= lag && away(k - lag)) {
      s1l += v * (second_difference(x, k - lag, m) - mean_all);
      ++pairs_l;
    }
  }
  if (count < 2 || pairs < 1 || pairs_l < 1) return s;
  const double shift = s1 / static_cast<double>(count);
  s.mean = mean_all + shift;
  const double var = s2 / static_cast<double>(count) - shift * shift;
  s.rms = std::sqrt(std::max(var, 0.0));
  if (!(s.rms > 0.0)) return s;
  // The correlation's slope near zero, C: the larger of its lag-1 drop and its secant to lag
  // L. White FM gives 3 / 2m from both; a process smooth over a few samples (a Gauss-Markov
  // effect's short correlation) drops little at lag 1 but as white FM by lag L, where the
  // maximum's excursions are decided.
  const double rho1 = (s11 / static_cast<double>(pairs) - shift * shift) / var;
  const double rho_l = (s1l / static_cast<double>(pairs_l) - shift * shift) / var;
  const double slope =
      std::clamp(std::max(1.0 - rho1, (1.0 - rho_l) / static_cast<double>(lag)), 0.0, 1.0);
  s.d = second_difference(x, s.k, m) - s.mean;
  double nu = std::numeric_limits<double>::infinity();
  for (int alpha = -2; alpha <= 2; ++alpha)
    nu = std::min(nu, edf_greenhall(alpha, kOverlappingAllan, m, n + 1));
  const double u = std::abs(s.d) / s.rms, w = static_cast<double>(windows);
  const double crossings = std::min(w, 1.0 + slope * w * u * u);
  s.p = std::min(1.0, crossings * student_t_two_sided(u, std::max(nu, 1.0)));
  const double sign = s.d > 0.0 ? 1.0 : -1.0;
  for (const std::int64_t k : {s.k - m, s.k + m})
    if (k >= 0 && k < windows &&
        sign * (second_difference(x, k, m) - s.mean) < -0.5 * std::abs(s.d))
      s.spike = true;
  return s;
}

}  // namespace

StepWitness find_step(std::span<const double> rate, double rate_hz, std::span<const Step> known,
                      double false_alarm) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("find_step: rate_hz must be finite and > 0");
  if (!(false_alarm > 0.0 && false_alarm < 1.0))
    throw std::invalid_argument("find_step: false_alarm must be in (0, 1)");
  StepWitness w;
  w.false_alarm = false_alarm;
  const auto n = static_cast<std::int64_t>(rate.size());
  // Too short for 16 independent windows at m = 2 (nu = 15), or with gaps: no search.
  if (n < 68 || std::any_of(rate.begin(), rate.end(), [](double v) { return std::isnan(v); }))
    return w;
  w.searched = true;
  // The phase of the record with the known jumps removed, sample k counting the part of itself
  // after each jump (kernels/simulate/simulate.hpp), centred so the sums stay small.
  double mean = 0.0;
  for (const double v : rate)
    mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> y(rate.size()), x(static_cast<std::size_t>(n) + 1, 0.0);
  for (std::size_t k = 0; k < y.size(); ++k)
    y[k] = rate[k] - mean;
  add_steps(y, known, rate_hz, -1.0);
  for (std::size_t k = 0; k < y.size(); ++k)
    x[k + 1] = x[k] + y[k];
  // Scales m = 1, 2, 4, ... while the record holds 16 non-overlapping pairs of means.
  std::vector<ScaleScan> scans;
  for (std::int64_t m = 1; (n - 2 * m + 1) / (2 * m) >= 16; m *= 2)
    scans.push_back(scan_scale(x, n, m));
  const auto n_scales = static_cast<double>(scans.size());
  // A jump persists at larger scales (D about d there too, the windows centred on it); a short
  // burst (a knock: a few samples of both signs) is a large D at small m that halves with each
  // doubling. A candidate that does not keep half its size at 2m and 4m is not a jump (at 2m
  // alone a burst keeps about half).
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ScaleScan& sc = scans[i];
    const double sign = sc.d > 0.0 ? 1.0 : -1.0;
    for (std::int64_t wide = 2 * sc.m; wide <= 4 * sc.m && !sc.spike; wide *= 2) {
      const std::int64_t k_wide = sc.k + sc.m - wide;  // centred on the boundary k + m
      if (k_wide < 0 || k_wide + 2 * wide > n) continue;
      // The scale's mean (the ramp's constant D), from its scan where there is one.
      double mean_wide = 0.0;
      const auto scanned =
          std::find_if(scans.begin(), scans.end(), [&](const ScaleScan& t) { return t.m == wide; });
      if (scanned != scans.end()) {
        mean_wide = scanned->mean;
      } else {
        for (std::int64_t k = 0; k + 2 * wide <= n; ++k)
          mean_wide += second_difference(x, k, wide);
        mean_wide /= static_cast<double>(n - 2 * wide + 1);
      }
      if (sign * (second_difference(x, k_wide, wide) - mean_wide) < 0.5 * std::abs(sc.d))
        sc.spike = true;
    }
  }
  std::size_t best_i = scans.size();
  for (std::size_t i = 0; i < scans.size(); ++i)
    if (!scans[i].spike && scans[i].rms > 0.0 &&
        (best_i == scans.size() || scans[i].p < scans[best_i].p))
      best_i = i;
  if (best_i == scans.size()) return w;
  const ScaleScan* best = &scans[best_i];
  std::int64_t jump = best->k + best->m;
  w.scale_m = best->m;
  w.statistic = std::abs(best->d) / best->rms;
  w.p_value = std::min(1.0, n_scales * best->p);
  // The jump's time from ever finer scales, each searched within the coarser one's reach, for
  // as long as the jump stands out by 3 rms there. Flicker and random walk move the largest
  // window by up to about that scale (measured: FindStep.NamesAJumpOfAFewRmsWithItsTimeAndSize),
  // so the finest scale is the time's uncertainty.
  std::int64_t finest = best->m;
  const double sign = best->d > 0.0 ? 1.0 : -1.0;
  for (std::size_t s = best_i; s-- > 0;) {
    const ScaleScan& sc = scans[s];
    const std::int64_t lo = std::max<std::int64_t>(0, jump - sc.m - 2 * sc.m);
    const std::int64_t hi = std::min<std::int64_t>(n - 2 * sc.m, jump - sc.m + 2 * sc.m);
    double top = -1.0;
    std::int64_t at = -1;
    for (std::int64_t k = lo; k <= hi; ++k) {
      const double v = sign * (second_difference(x, k, sc.m) - sc.mean);
      if (v > top) {
        top = v;
        at = k;
      }
    }
    if (at < 0 || !(top > 3.0 * sc.rms)) break;
    jump = at + sc.m;
    finest = sc.m;
  }
  // The size from the best scale, its windows centred on the jump; a jump known already (the
  // residual of an imperfect removal) is not a new one.
  const std::int64_t k = std::clamp<std::int64_t>(jump - best->m, 0, n - 2 * best->m);
  // Its uncertainty: the windows' rms, and the triangle's drop over half the finest scale
  // (the time's error moves the windows off the jump's centre).
  w.size = second_difference(x, k, best->m) - best->mean;
  const double drift = std::abs(w.size) * 0.5 * static_cast<double>(finest) / best->m;
  w.size_sigma = std::hypot(best->rms, drift);
  w.time_s = static_cast<double>(jump) / rate_hz;
  w.time_sigma_s = static_cast<double>(finest) / rate_hz;
  for (const Step& st : known)
    if (std::abs(st.time_s - w.time_s) * rate_hz < 2.0 * static_cast<double>(best->m)) {
      w.note = "the largest excursion is at a known step's time";
      return w;
    }
  w.found = w.p_value < false_alarm;
  return w;
}

}  // namespace allanlot::kernels
