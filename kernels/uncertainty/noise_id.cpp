#include "kernels/uncertainty/noise_id.hpp"

#include "kernels/allan/allan.hpp"
#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

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
    const int dmax = stat_info(s).noise_id_dmax;
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
  if (out.alpha == 1 && stat_info(s).differences.modified) {
    // R(n) = MVAR / AVAR separates white from flicker PM, which B1 cannot. TDEV is
    // tau / sqrt(3) MDEV (SP1065 eq. (16)).
    const double tau = static_cast<double>(m) * p.tau0_s;
    const double mvar =
        is_time_error(s) ? 3.0 * r.dev[i] * r.dev[i] / (tau * tau) : r.dev[i] * r.dev[i];
    const double oavar = allan_variance(p, m, 1);
    if (oavar > 0.0 && std::isfinite(mvar)) out.alpha = alpha_from_rn(mvar / oavar, m);
  }
  return out;
}

// lag1_autocorrelation (header) over the values g(0) .. g(n-1), without materializing them.
// Each sum has four interleaved partial sums (term t goes to lane t mod 4, lanes added as
// (0 + 1) + (2 + 3)) and missing values contribute a zero instead of a branch: one running
// sum would wait on the add latency at every term, and noise identification reads the record
// about thirty times per channel. A fixed order still, so the same bits for any thread count.
template <class G>
double lag1_of(G g, std::int64_t n_values) {
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  std::int64_t count[4] = {0, 0, 0, 0};
  const auto add_value = [&](std::int64_t t, int lane) {
    const double v = g(t);
    const bool ok = std::isfinite(v);
    sum[lane] += ok ? v : 0.0;
    count[lane] += ok ? 1 : 0;
  };
  std::int64_t t = 0;
  for (; t + 4 <= n_values; t += 4) {
#pragma GCC unroll 4
    for (int l = 0; l < 4; ++l)
      add_value(t + l, l);
  }
  for (; t < n_values; ++t)
    add_value(t, static_cast<int>(t & 3));
  const std::int64_t n = (count[0] + count[1]) + (count[2] + count[3]);
  if (n < 2) return 0.0;
  const double mean = ((sum[0] + sum[1]) + (sum[2] + sum[3])) / static_cast<double>(n);
  double num[4] = {0.0, 0.0, 0.0, 0.0}, den[4] = {0.0, 0.0, 0.0, 0.0};
  const auto add_pair = [&](std::int64_t u, int lane) {
    const double v = g(u);
    const double w = u + 1 < n_values ? g(u + 1) : std::numeric_limits<double>::quiet_NaN();
    const bool ok = std::isfinite(v);
    const double a = ok ? v - mean : 0.0;
    den[lane] += a * a;
    num[lane] += ok && std::isfinite(w) ? a * (w - mean) : 0.0;
  };
  t = 0;
  for (; t + 5 <= n_values; t += 4) {  // t + 4 < n_values: every g(u + 1) exists
#pragma GCC unroll 4
    for (int l = 0; l < 4; ++l)
      add_pair(t + l, l);
  }
  for (; t < n_values; ++t)
    add_pair(t, static_cast<int>(t & 3));
  const double d = (den[0] + den[1]) + (den[2] + den[3]);
  if (!(d > 0.0)) return 0.0;
  return static_cast<double>(n - 1) / static_cast<double>(n) *
         ((num[0] + num[1]) + (num[2] + num[3])) / d;
}

double delta_of(double r1) {
  return r1 / (1.0 + r1);
}

// True when the lag-1 method stops at level d (noise_id_lag1's rule): stationary, at dmax, or
// fewer than 3 values left (level 0 has nz values, level d >= 1 has nz - d).
bool stops_at(double delta, int d, int dmax, std::int64_t nz) {
  return delta < kDeltaStationary || d >= dmax || nz - d < 3;
}

std::vector<std::vector<double>> lag1_deltas_swept(const PhaseData& p,
                                                   std::span<const std::int64_t> ms, int dmax);

// delta at the differencing levels 0, 1, ... up to where the method stops for dmax. Gap-free
// records (dmax <= 3, every caller) take the multi-m sweep below with this one m: it computes
// each level's values on the fly from the phase instead of storing a decimated copy per level
// (for m = 1 that copy was the size of the record), with the same sums as the stored path.
std::vector<double> lag1_deltas(const PhaseData& p, std::int64_t m, int dmax) {
  if (m < 1) throw std::invalid_argument("noise_id_lag1: m must be >= 1, got " + std::to_string(m));
  if (dmax < 1)
    throw std::invalid_argument("noise_id_lag1: dmax must be >= 1, got " + std::to_string(dmax));
  const std::int64_t nz = (p.n_points() - 1) / m + 1;
  if (nz < 2)
    throw std::invalid_argument("noise_id_lag1: fewer than 2 phase points at m = " +
                                std::to_string(m));
  if (!p.has_gaps() && dmax <= 3) return lag1_deltas_swept(p, std::span(&m, 1), dmax).front();
  std::vector<double> deltas;
  // Level 0 is the decimated phase itself; from level 1 on, the differences, which are the
  // m-sample rate averages (NaN across gaps) and their differences.
  std::vector<double> z(static_cast<std::size_t>(nz));
  for (std::int64_t k = 0; k < nz; ++k)
    z[static_cast<std::size_t>(k)] = p.x[static_cast<std::size_t>(k * m)];
  for (int d = 0;; ++d) {
    deltas.push_back(delta_of(lag1_autocorrelation(z)));
    if (stops_at(deltas.back(), d, dmax, nz)) return deltas;
    z = d == 0 ? rate_averages(p, m) : difference(z);
  }
}

// Values of the differencing level D at index t of a gap-free record decimated by m: level 0
// the phase x_{t m}, level 1 the m-sample rate average (rate_averages' expression), level
// D + 1 the difference of level D (the same operations as lag1_deltas' levels).
template <int D>
double level_value(const double* x, std::int64_t m, double scale, std::int64_t t) {
  if constexpr (D == 0)
    return x[t * m];
  else if constexpr (D == 1)
    return (x[(t + 1) * m] - x[t * m]) * scale;
  else
    return level_value<D - 1>(x, m, scale, t + 1) - level_value<D - 1>(x, m, scale, t);
}

// One m's lag-1 sums at one level, carried from tile to tile of the sweep below.
struct SweepRun {
  std::int64_t m = 1, nz = 0;
  double scale = 1.0;
  std::vector<double> deltas;
  bool active = true;
  double sum[4] = {0.0, 0.0, 0.0, 0.0}, num[4] = {0.0, 0.0, 0.0, 0.0},
         den[4] = {0.0, 0.0, 0.0, 0.0};
  double mean = 0.0, a_prev = 0.0;
};

// Positions of the record per tile of the sweep: 256 KiB of phase, read from L2 by every m.
constexpr std::int64_t kSweepTile = std::int64_t{1} << 15;

// Pass A (sums, for the mean) or pass B (num and den about the mean) of level D for every
// active run, walking the record once in tiles: the indices t of a run whose position t m
// falls in the tile are handled while the tile is in cache. Each run adds its values in
// increasing t to lane t mod 4, exactly the order of lag1_of.
template <int D, bool kPassB>
void sweep_level(const double* x, std::int64_t n_points, std::vector<SweepRun*>& runs) {
  for (std::int64_t x0 = 0; x0 < n_points; x0 += kSweepTile) {
    const std::int64_t x1 = std::min(n_points, x0 + kSweepTile);
    for (SweepRun* r : runs) {
      const std::int64_t m = r->m, n = r->nz - D;
      const std::int64_t tb = (x0 + m - 1) / m, te = std::min(n, (x1 + m - 1) / m);
      if (tb >= te) continue;
      const auto g = [x, m, scale = r->scale](std::int64_t t) {
        return level_value<D>(x, m, scale, t);
      };
      // The lanes live in locals for the loop (an array indexed by t & 3 would go through
      // memory at every term); head and tail terms pick their lane with a switch.
      if constexpr (!kPassB) {
        double s0 = r->sum[0], s1 = r->sum[1], s2 = r->sum[2], s3 = r->sum[3];
        const auto add = [&](std::int64_t t) {
          const double v = g(t);
          switch (t & 3) {
          case 0:
            s0 += v;
            break;
          case 1:
            s1 += v;
            break;
          case 2:
            s2 += v;
            break;
          default:
            s3 += v;
            break;
          }
        };
        std::int64_t t = tb;
        for (; t < te && (t & 3) != 0; ++t)
          add(t);
        for (; t + 4 <= te; t += 4) {
          s0 += g(t);
          s1 += g(t + 1);
          s2 += g(t + 2);
          s3 += g(t + 3);
        }
        for (; t < te; ++t)
          add(t);
        r->sum[0] = s0, r->sum[1] = s1, r->sum[2] = s2, r->sum[3] = s3;
      } else {
        const double mean = r->mean;
        double a_prev = r->a_prev;
        double d0 = r->den[0], d1 = r->den[1], d2 = r->den[2], d3 = r->den[3];
        double n0 = r->num[0], n1 = r->num[1], n2 = r->num[2], n3 = r->num[3];
        const auto add = [&](std::int64_t t) {
          const double a = g(t) - mean;
          const double pa = t > 0 ? a_prev * a : 0.0;  // num lane (t - 1) & 3
          switch (t & 3) {
          case 0:
            d0 += a * a;
            if (t > 0) n3 += pa;
            break;
          case 1:
            d1 += a * a;
            n0 += pa;
            break;
          case 2:
            d2 += a * a;
            n1 += pa;
            break;
          default:
            d3 += a * a;
            n2 += pa;
            break;
          }
          a_prev = a;
        };
        std::int64_t t = tb;
        for (; t < te && ((t & 3) != 0 || t == 0); ++t)
          add(t);
        for (; t + 4 <= te; t += 4) {
          const double a0 = g(t) - mean, a1 = g(t + 1) - mean, a2 = g(t + 2) - mean,
                       a3 = g(t + 3) - mean;
          n3 += a_prev * a0;
          d0 += a0 * a0;
          n0 += a0 * a1;
          d1 += a1 * a1;
          n1 += a1 * a2;
          d2 += a2 * a2;
          n2 += a2 * a3;
          d3 += a3 * a3;
          a_prev = a3;
        }
        for (; t < te; ++t)
          add(t);
        r->den[0] = d0, r->den[1] = d1, r->den[2] = d2, r->den[3] = d3;
        r->num[0] = n0, r->num[1] = n1, r->num[2] = n2, r->num[3] = n3;
        r->a_prev = a_prev;
      }
    }
  }
}

// lag1_deltas for many m of one gap-free record at once: each level is two sweeps over the
// record for all m still differencing, instead of two passes per m (the decimated reads of
// the small m each touch every cache line of the record: ~60 passes over 43 MB per channel
// before). Same sums in the same order as lag1_of on finite values (a missing value adds
// +0.0 there, which changes no sum), so the same bits; where a sum overflows, that m's level is
// recomputed by lag1_of, which leaves non-finite values out.
std::vector<std::vector<double>> lag1_deltas_swept(const PhaseData& p,
                                                   std::span<const std::int64_t> ms, int dmax) {
  std::vector<SweepRun> runs(ms.size());
  for (std::size_t i = 0; i < ms.size(); ++i) {
    if (ms[i] < 1 || dmax < 1 || dmax > 3 || (p.n_points() - 1) / ms[i] + 1 < 2)
      throw std::invalid_argument("lag1_deltas_swept: bad m or dmax");  // callers check first
    runs[i].m = ms[i];
    runs[i].nz = (p.n_points() - 1) / ms[i] + 1;
    runs[i].scale = 1.0 / (static_cast<double>(ms[i]) * p.tau0_s);
  }
  const double* x = p.x.data();
  for (int d = 0; d <= 3; ++d) {
    std::vector<SweepRun*> active;
    for (SweepRun& r : runs)
      if (r.active) {
        r = SweepRun{r.m, r.nz, r.scale, std::move(r.deltas), true};
        if (r.nz - d >= 2) active.push_back(&r);
      }
    const auto sweep = [&](auto pass_b) {
      constexpr bool kB = decltype(pass_b)::value;
      if (d == 0) sweep_level<0, kB>(x, p.n_points(), active);
      if (d == 1) sweep_level<1, kB>(x, p.n_points(), active);
      if (d == 2) sweep_level<2, kB>(x, p.n_points(), active);
      if (d == 3) sweep_level<3, kB>(x, p.n_points(), active);
    };
    sweep(std::false_type{});
    for (SweepRun* r : active)
      r->mean =
          ((r->sum[0] + r->sum[1]) + (r->sum[2] + r->sum[3])) / static_cast<double>(r->nz - d);
    sweep(std::true_type{});
    bool any = false;
    for (SweepRun& r : runs) {
      if (!r.active) continue;
      const std::int64_t n = r.nz - d;
      double r1 = 0.0;
      if (n >= 2) {
        const double den = (r.den[0] + r.den[1]) + (r.den[2] + r.den[3]);
        const double num = (r.num[0] + r.num[1]) + (r.num[2] + r.num[3]);
        if (!std::isfinite(den) || !std::isfinite(num) || !std::isfinite(r.mean)) {
          const std::int64_t m = r.m;
          const double scale = r.scale;
          if (d == 0)
            r1 = lag1_of([&](std::int64_t t) { return level_value<0>(x, m, scale, t); }, n);
          if (d == 1)
            r1 = lag1_of([&](std::int64_t t) { return level_value<1>(x, m, scale, t); }, n);
          if (d == 2)
            r1 = lag1_of([&](std::int64_t t) { return level_value<2>(x, m, scale, t); }, n);
          if (d == 3)
            r1 = lag1_of([&](std::int64_t t) { return level_value<3>(x, m, scale, t); }, n);
        } else if (den > 0.0) {
          const auto nd = static_cast<double>(n);
          r1 = (nd - 1.0) / nd * num / den;
        }
      }
      r.deltas.push_back(delta_of(r1));
      r.active = !stops_at(r.deltas.back(), d, dmax, r.nz);
      any = any || r.active;
    }
    if (!any) break;
  }
  std::vector<std::vector<double>> out;
  out.reserve(runs.size());
  for (SweepRun& r : runs)
    out.push_back(std::move(r.deltas));
  return out;
}

// The estimate for dmax from the deltas of a run with the same or another dmax; nullopt when
// that run stopped (at its own dmax) before the level where this one stops.
std::optional<Lag1Estimate> select_level(const std::vector<double>& deltas, std::int64_t nz,
                                         int dmax) {
  for (int d = 0; d < static_cast<int>(deltas.size()); ++d)
    if (stops_at(deltas[static_cast<std::size_t>(d)], d, dmax, nz)) {
      Lag1Estimate e;
      e.delta = deltas[static_cast<std::size_t>(d)];
      e.d = d;
      const int p_exp = -static_cast<int>(std::lround(2.0 * e.delta)) - 2 * e.d;
      e.alpha = std::clamp(p_exp + 2, -2, 2);
      return e;
    }
  return std::nullopt;
}
}  // namespace

double lag1_autocorrelation(std::span<const double> z) {
  return lag1_of([z](std::int64_t t) { return z[static_cast<std::size_t>(t)]; },
                 static_cast<std::int64_t>(z.size()));
}

Lag1Estimate noise_id_lag1(const PhaseData& p, std::int64_t m, int dmax) {
  return *select_level(lag1_deltas(p, m, dmax), (p.n_points() - 1) / m + 1, dmax);
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
  const std::int64_t nz = (p.n_points() - 1) / m + 1;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (const auto it = deltas_.find(m); it != deltas_.end())
      if (const auto e = select_level(it->second, nz, dmax)) return *e;
  }
  // Outside the lock: rows run in parallel. A run for dmax 3 answers dmax 2 as well (its
  // levels are a superset); a dmax 2 run answers dmax 3 unless it stopped at level 2.
  std::vector<double> deltas = lag1_deltas(p, m, dmax);
  const Lag1Estimate e = *select_level(deltas, nz, dmax);
  const std::lock_guard<std::mutex> lock(mutex_);
  auto& stored = deltas_[m];
  if (deltas.size() > stored.size()) stored = std::move(deltas);
  return e;
}

void Lag1Cache::prefetch(const PhaseData& p, std::span<const std::int64_t> ms, int dmax,
                         int nthreads) {
  if (p.has_gaps() || dmax > 3) return;  // gapped records keep the per-m path
  std::vector<std::int64_t> todo;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const std::int64_t m : ms) {
      if (m < 1 || (p.n_points() - 1) / m + 1 < 2) continue;
      const auto it = deltas_.find(m);
      if (it == deltas_.end() || !select_level(it->second, (p.n_points() - 1) / m + 1, dmax))
        todo.push_back(m);
    }
  }
  if (todo.empty()) return;
  // One sweep per thread over an interleaved share of the m (each share mixes small and large
  // m, so the shares cost about the same); an m's deltas do not depend on its share.
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
  const auto shares = static_cast<std::int64_t>(
      std::min<std::size_t>(static_cast<std::size_t>(std::max(nt, 1)), todo.size()));
  std::vector<std::vector<std::int64_t>> share_m(static_cast<std::size_t>(shares));
  for (std::size_t i = 0; i < todo.size(); ++i)
    share_m[i % static_cast<std::size_t>(shares)].push_back(todo[i]);
  std::vector<std::vector<std::vector<double>>> share_deltas(static_cast<std::size_t>(shares));
  ExceptionCollector errors;
#pragma omp parallel for num_threads(nt) schedule(static, 1)
  for (std::int64_t sh = 0; sh < shares; ++sh)
    errors.run([&] {
      const auto su = static_cast<std::size_t>(sh);
      share_deltas[su] = lag1_deltas_swept(p, share_m[su], dmax);
    });
  errors.rethrow();
  const std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t sh = 0; sh < share_m.size(); ++sh)
    for (std::size_t i = 0; i < share_m[sh].size(); ++i) {
      auto& stored = deltas_[share_m[sh][i]];
      if (share_deltas[sh][i].size() > stored.size()) stored = std::move(share_deltas[sh][i]);
    }
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
  // The lag-1 rows of a gap-free record in one sweep for all their m (Lag1Cache::prefetch),
  // then each row reads its estimate; same values as noise_id_lag1 row by row.
  Lag1Cache local;
  Lag1Cache* lag1 = cache ? cache : &local;
  std::vector<std::int64_t> lag1_m;
  for (std::size_t i = 0; i < rows; ++i)
    if ((p.n_points() - 1) / r.m[i] >= kLag1MinPoints) lag1_m.push_back(r.m[i]);
  lag1->prefetch(p, lag1_m, stat_info(s).noise_id_dmax, nthreads);
  std::vector<RowId> ids(rows);
  ExceptionCollector errors;
  const std::int64_t count = static_cast<std::int64_t>(rows);
  // One row per iteration, each written by one thread: the result is independent of the
  // thread count.
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t i = 0; i < count; ++i)
    errors.run([&] {
      ids[static_cast<std::size_t>(i)] = identify_row(s, p, r, static_cast<std::size_t>(i), lag1);
    });
  errors.rethrow();
  std::vector<int> alpha(rows);
  for (std::size_t i = 0; i < rows; ++i)
    alpha[i] = ids[i].keep_previous ? alpha[i - 1] : ids[i].alpha;
  return alpha;
}

}  // namespace allanlot::kernels
