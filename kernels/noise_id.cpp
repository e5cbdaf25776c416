#include "kernels/noise_id.hpp"

#include "kernels/allan.hpp"
#include "kernels/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Riley & Greenhall 2004: the differencing stops once delta < 0.25, where the differenced
// series is stationary.
constexpr double kDeltaStationary = 0.25;
// Stable32 (and SP1065 sec. 5.6.4) use the lag-1 method from 30 analysis points on.
constexpr std::int64_t kLag1MinPoints = 30;

std::vector<double> difference(const std::vector<double>& z) {
  std::vector<double> out(z.size() > 0 ? z.size() - 1 : 0);
  for (std::size_t i = 0; i + 1 < z.size(); ++i)
    out[i] = z[i + 1] - z[i];  // NaN propagates: a difference touching a gap is missing
  return out;
}

// Non-overlapping m-sample rate averages (in phase units per tau0, i.e. the m-sample phase
// increments divided by m tau0); NaN where the increment crosses a gap.
std::vector<double> rate_averages(const PhaseData& p, std::int64_t m) {
  const std::int64_t nf = (p.n_points() - 1) / m;
  std::vector<double> y(static_cast<std::size_t>(std::max<std::int64_t>(nf, 0)));
  const double scale = 1.0 / (static_cast<double>(m) * p.tau0_s);
  for (std::int64_t k = 0; k < nf; ++k) {
    const std::int64_t a = k * m, b = (k + 1) * m;
    y[static_cast<std::size_t>(k)] =
        p.clean(a, b)
            ? (p.x[static_cast<std::size_t>(b)] - p.x[static_cast<std::size_t>(a)]) * scale
            : kNaN;
  }
  return y;
}

// Sample variance (n - 1 denominator) of the finite values, and their count.
std::pair<double, std::int64_t> sample_variance(const std::vector<double>& y) {
  double mean = 0.0;
  std::int64_t n = 0;
  for (const double v : y)
    if (std::isfinite(v)) {
      mean += v;
      ++n;
    }
  if (n < 2) return {kNaN, n};
  mean /= static_cast<double>(n);
  double s = 0.0;
  for (const double v : y)
    if (std::isfinite(v)) s += (v - mean) * (v - mean);
  return {s / static_cast<double>(n - 1), n};
}

double allan_variance(const PhaseData& p, std::int64_t m, std::int64_t stride) {
  const auto sc = detail::second_difference_core(p, m, stride);
  const double tau = static_cast<double>(m) * p.tau0_s;
  return sc.n > 0 ? sc.sum / (2.0 * tau * tau * static_cast<double>(sc.n)) : kNaN;
}

int stable32_dmax(Stat s) {
  return (s == Stat::Hdev || s == Stat::Ohdev) ? 3 : 2;
}

// The alpha at row i when it does not depend on the previous row; `keep_previous` rows are
// resolved afterwards in increasing m.
struct RowId {
  int alpha = 0;
  bool keep_previous = false;
};

RowId identify_row(Stat s, const PhaseData& p, const StatResult& r, std::size_t i,
                   Lag1Cache* cache) {
  const std::int64_t m = r.m[i];
  const std::int64_t nf = (p.n_points() - 1) / m;
  RowId out;
  if (nf >= kLag1MinPoints) {
    const int dmax = stable32_dmax(s);
    out.alpha = (cache ? cache->get(p, m, dmax) : noise_id_lag1(p, m, dmax)).alpha;
    return out;
  }
  if (2 * m > max_m(s, p.n_points()) && i > 0) {
    out.keep_previous = true;
    return out;
  }
  // B1 ratio: Stable32 compares the standard variance with the non-overlapping Allan variance
  // of the same tau for every statistic (HDEV and OHDEV print the alphas of ADEV and OADEV; with
  // TOTVAR or the overlapping AVAR in the denominator, PHASE.DAT's all-tau TOTDEV alphas are
  // missed at 51 and 102 of 185 rows, with the non-overlapping AVAR at none). The statistics
  // differ through N = r.n, their number of terms.
  const auto [svar, n_avg] = sample_variance(rate_averages(p, m));
  const double avar = allan_variance(p, m, m);
  if (!(n_avg >= 2 && avar > 0.0 && std::isfinite(svar))) {
    // Too little for any estimate (e.g. two averages around a gap): white FM, the noise of
    // the statistic's reference case, rather than an arbitrary neighbour.
    out.alpha = 0;
    return out;
  }
  out.alpha = alpha_from_b1(svar / avar, static_cast<double>(std::max<std::int64_t>(r.n[i], 2)));
  if (out.alpha == 1 && (s == Stat::Mdev || s == Stat::Tdev)) {
    // R(n) = MVAR / AVAR separates white from flicker PM, which B1 cannot.
    const double tau = static_cast<double>(m) * p.tau0_s;
    const double mvar =
        s == Stat::Mdev ? r.dev[i] * r.dev[i] : 3.0 * r.dev[i] * r.dev[i] / (tau * tau);
    const double oavar = allan_variance(p, m, 1);
    if (oavar > 0.0 && std::isfinite(mvar)) out.alpha = alpha_from_rn(mvar / oavar, m);
  }
  return out;
}

}  // namespace

double lag1_autocorrelation(std::span<const double> z) {
  double mean = 0.0;
  std::int64_t n = 0;
  for (const double v : z)
    if (std::isfinite(v)) {
      mean += v;
      ++n;
    }
  if (n < 2) return 0.0;
  mean /= static_cast<double>(n);
  double num = 0.0, den = 0.0;
  for (std::size_t t = 0; t < z.size(); ++t) {
    if (!std::isfinite(z[t])) continue;
    const double a = z[t] - mean;
    den += a * a;
    if (t + 1 < z.size() && std::isfinite(z[t + 1])) num += a * (z[t + 1] - mean);
  }
  if (!(den > 0.0)) return 0.0;
  return static_cast<double>(n - 1) / static_cast<double>(n) * num / den;
}

Lag1Estimate noise_id_lag1(const PhaseData& p, std::int64_t m, int dmax) {
  if (m < 1) throw std::invalid_argument("noise_id_lag1: m must be >= 1, got " + std::to_string(m));
  if (dmax < 1)
    throw std::invalid_argument("noise_id_lag1: dmax must be >= 1, got " + std::to_string(dmax));
  const std::int64_t nz = (p.n_points() - 1) / m + 1;
  if (nz < 2)
    throw std::invalid_argument("noise_id_lag1: fewer than 2 phase points at m = " +
                                std::to_string(m));
  // Level 0 is the decimated phase itself; from level 1 on, the differences, which are the
  // m-sample rate averages (NaN across gaps) and their differences.
  std::vector<double> z(static_cast<std::size_t>(nz));
  for (std::int64_t k = 0; k < nz; ++k)
    z[static_cast<std::size_t>(k)] = p.x[static_cast<std::size_t>(k * m)];
  Lag1Estimate e;
  for (;;) {
    const double r1 = lag1_autocorrelation(z);
    e.delta = r1 / (1.0 + r1);
    if (e.delta < kDeltaStationary || e.d >= dmax || z.size() < 3) break;
    z = e.d == 0 ? rate_averages(p, m) : difference(z);
    ++e.d;
  }
  const int p_exp = -static_cast<int>(std::lround(2.0 * e.delta)) - 2 * e.d;
  e.alpha = std::clamp(p_exp + 2, -2, 2);
  return e;
}

double b1_expected(double n, int mu) {
  if (mu == 0) return n * std::log(n) / (2.0 * (n - 1.0) * std::numbers::ln2);
  return n * (1.0 - std::pow(n, mu)) / (2.0 * (n - 1.0) * (1.0 - std::pow(2.0, mu)));
}

int alpha_from_b1(double b1, double n) {
  // mu = 1, 0, -1 are random walk, flicker and white FM (alpha = -2, -1, 0); below the last
  // boundary mu = -2 (PM noise).
  for (int mu = 1; mu >= -1; --mu) {
    const double boundary = std::sqrt(b1_expected(n, mu) * b1_expected(n, mu - 1));
    if (b1 > boundary) return -mu - 1;
  }
  return 1;
}

double rn_expected(std::int64_t m, int alpha) {
  const double md = static_cast<double>(m);
  if (alpha == 1) return 3.37 / (1.04 + 3.0 * std::log(std::numbers::pi * md));
  if (alpha == 2) return 1.0 / md;
  throw std::invalid_argument("rn_expected: alpha must be 1 or 2, got " + std::to_string(alpha));
}

int alpha_from_rn(double rn, std::int64_t m) {
  const double boundary = std::sqrt(rn_expected(m, 1) * rn_expected(m, 2));
  return rn > boundary ? 1 : 2;
}

Lag1Estimate Lag1Cache::get(const PhaseData& p, std::int64_t m, int dmax) {
  const auto key = std::make_pair(m, dmax);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (const auto it = values_.find(key); it != values_.end()) return it->second;
  }
  const Lag1Estimate e = noise_id_lag1(p, m, dmax);  // outside the lock: rows run in parallel
  const std::lock_guard<std::mutex> lock(mutex_);
  values_.emplace(key, e);
  return e;
}

std::vector<int> identify_alpha(Stat s, const PhaseData& p, const StatResult& r, int nthreads,
                                Lag1Cache* cache) {
  const std::size_t rows = r.size();
  if (r.dev.size() != rows || r.n.size() != rows)
    throw std::invalid_argument("identify_alpha: m, dev and n must have equal lengths");
  for (std::size_t i = 0; i < rows; ++i) {
    if (r.m[i] < 1 || (p.n_points() - 1) / r.m[i] < 1)
      throw std::invalid_argument("identify_alpha: m = " + std::to_string(r.m[i]) +
                                  " has no full average in " + std::to_string(p.n_points()) +
                                  " phase points");
    if (i > 0 && r.m[i] <= r.m[i - 1])
      throw std::invalid_argument("identify_alpha: rows must be in increasing m");
  }
  std::vector<RowId> ids(rows);
  ExceptionCollector errors;
  const std::int64_t count = static_cast<std::int64_t>(rows);
  // One row per iteration, each written by one thread: the result is independent of the
  // thread count.
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t i = 0; i < count; ++i)
    errors.run([&] {
      ids[static_cast<std::size_t>(i)] = identify_row(s, p, r, static_cast<std::size_t>(i), cache);
    });
  errors.rethrow();
  std::vector<int> alpha(rows);
  for (std::size_t i = 0; i < rows; ++i)
    alpha[i] = ids[i].keep_previous ? alpha[i - 1] : ids[i].alpha;
  return alpha;
}

}  // namespace allanlot::kernels
