#include "kernels/uncertainty/hat.hpp"

#include "kernels/allan/codev.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_pair(const PhaseData& a, const PhaseData& b, const std::string& what) {
  if (a.n_points() != b.n_points())
    throw std::invalid_argument(what + ": the records have " + std::to_string(a.n_points()) +
                                " and " + std::to_string(b.n_points()) +
                                " phase points; they must be equally long");
  if (a.tau0_s != b.tau0_s)
    throw std::invalid_argument(what + ": the records' sample intervals differ (" +
                                std::to_string(a.tau0_s) + " s and " + std::to_string(b.tau0_s) +
                                " s)");
}

void check_confidence(double c) {
  if (!(c > 0.0 && c < 1.0))
    throw std::invalid_argument("confidence must be in (0, 1), got " + std::to_string(c));
}

// The m of m_list that OADEV evaluates on N points (max_m: Stable32's stop ratio 4).
std::vector<std::int64_t> oadev_ms(std::span<const std::int64_t> m_list, std::int64_t n_points) {
  const std::int64_t mmax = max_m(Stat::Oadev, n_points);
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : m_list) {
    if (m < 1) throw std::invalid_argument("m must be >= 1, got " + std::to_string(m));
    if (m <= mmax) ms.push_back(m);
  }
  return ms;
}

StatResult oadev_with_confidence(const PhaseData& p, std::span<const std::int64_t> ms,
                                 double confidence, int nthreads) {
  StatResult r = compute(Stat::Oadev, p, ms, nthreads);
  add_confidence(Stat::Oadev, p, r, confidence, nthreads);
  return r;
}

// The row of r at averaging factor m, or rows() when r has none.
std::size_t row_of(const StatResult& r, std::int64_t m) {
  return static_cast<std::size_t>(std::find(r.m.begin(), r.m.end(), m) - r.m.begin());
}

double variance(const StatResult& r, std::size_t i) {
  return r.dev[i] * r.dev[i];
}

// Appends a row for the signed variance v with edf nu: dev = sign(v) sqrt(|v|) and the
// chi-square interval of |dev| (SP1065 eq. (45)) given dev's sign. Without a usable edf (or for
// v <= 0 when !negative_interval) the interval and edf are NaN.
void push_row(StatResult& r, std::int64_t m, double tau_s, std::int64_t n, int alpha, double v,
              double nu, double confidence, bool negative_interval) {
  const double dev = std::copysign(std::sqrt(std::fabs(v)), v);
  const bool usable = (v > 0.0 || (negative_interval && v < 0.0)) && nu > 0.0 && std::isfinite(nu);
  r.m.push_back(m);
  r.tau_s.push_back(tau_s);
  r.n.push_back(n);
  r.alpha.push_back(alpha);
  r.dev.push_back(dev);
  if (!usable) {
    r.edf.push_back(kNaN);
    r.dev_lo.push_back(kNaN);
    r.dev_hi.push_back(kNaN);
    return;
  }
  const Interval ci = chi2_interval(std::fabs(dev), nu, confidence);
  r.edf.push_back(nu);
  r.dev_lo.push_back(dev > 0.0 ? ci.lo : -ci.hi);
  r.dev_hi.push_back(dev > 0.0 ? ci.hi : -ci.lo);
}

std::string taus_text(const std::vector<double>& taus) {
  std::string s;
  const std::size_t shown = std::min<std::size_t>(taus.size(), 6);
  for (std::size_t i = 0; i < shown; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.4g s", i ? ", " : "", taus[i]);
    s += buf;
  }
  if (shown < taus.size()) s += ", ...";
  return s;
}

}  // namespace

double hat_estimate_variance(double s_ab, double s_bc, double s_ca, double nu_ab, double nu_bc,
                             double nu_ca) {
  const double a = 0.5 * (s_ab + s_ca - s_bc);  // the clocks' variances, by the hat itself
  const double b = 0.5 * (s_ab + s_bc - s_ca);
  const double c = 0.5 * (s_bc + s_ca - s_ab);
  const double var_ab = 2.0 * s_ab * s_ab / nu_ab;
  const double var_bc = 2.0 * s_bc * s_bc / nu_bc;
  const double var_ca = 2.0 * s_ca * s_ca / nu_ca;
  const double cov_ab_ca = 2.0 * a * a / std::sqrt(nu_ab * nu_ca);  // share clock A
  const double cov_ab_bc = 2.0 * b * b / std::sqrt(nu_ab * nu_bc);  // share clock B
  const double cov_ca_bc = 2.0 * c * c / std::sqrt(nu_ca * nu_bc);  // share clock C
  return 0.25 * (var_ab + var_bc + var_ca + 2.0 * cov_ab_ca - 2.0 * cov_ab_bc - 2.0 * cov_ca_bc);
}

double codev_edf(double s_x, double s_y, double g, double nu_x, double nu_y) {
  if (g == 0.0) return 0.0;
  const double var = (s_x * s_y + g * g) / std::sqrt(nu_x * nu_y);
  return 2.0 * g * g / var;
}

HatResult three_cornered_hat(const PhaseData& ab, const PhaseData& bc, const PhaseData& ca,
                             std::span<const std::int64_t> m_list, double confidence,
                             int nthreads) {
  check_pair(ab, bc, "three-cornered hat: AB and BC");
  check_pair(ab, ca, "three-cornered hat: AB and CA");
  check_confidence(confidence);
  const std::vector<std::int64_t> ms = oadev_ms(m_list, ab.n_points());
  HatResult h;
  const PhaseData* pairs[3] = {&ab, &bc, &ca};
  for (int k = 0; k < 3; ++k)
    h.pair[k] = oadev_with_confidence(*pairs[k], ms, confidence, nthreads);
  const char* names[3] = {"A", "B", "C"};
  std::vector<double> negative[3];
  for (std::size_t i0 = 0; i0 < h.pair[0].size(); ++i0) {
    const std::int64_t m = h.pair[0].m[i0];
    const std::size_t row[3] = {i0, row_of(h.pair[1], m), row_of(h.pair[2], m)};
    if (row[1] == h.pair[1].size() || row[2] == h.pair[2].size()) continue;
    double s[3], nu[3];
    std::int64_t n = h.pair[0].n[i0];
    for (int k = 0; k < 3; ++k) {
      s[k] = variance(h.pair[k], row[k]);
      nu[k] = h.pair[k].edf[row[k]];
      n = std::min(n, h.pair[k].n[row[k]]);
    }
    // Clock i shares pairs i and i + 2 (mod 3) and is absent from pair i + 1: A from AB, CA
    // without BC; B from BC, AB without CA; C from CA, BC without AB.
    for (int i = 0; i < 3; ++i) {
      const int p = i, q = (i + 1) % 3, r = (i + 2) % 3;
      const double v = 0.5 * (s[p] + s[r] - s[q]);
      const double var_v = hat_estimate_variance(s[p], s[q], s[r], nu[p], nu[q], nu[r]);
      const double edf = v > 0.0 && var_v > 0.0 ? 2.0 * v * v / var_v : kNaN;
      const int alpha = std::min(h.pair[p].alpha[row[p]], h.pair[r].alpha[row[r]]);
      push_row(h.clock[i], m, h.pair[0].tau_s[i0], n, alpha, v, edf, confidence, false);
      if (!(v > 0.0)) negative[i].push_back(h.pair[0].tau_s[i0]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    h.clock[i].confidence = confidence;
    if (negative[i].empty()) continue;
    h.notes[i] = "clock " + std::string(names[i]) + ": variance estimate <= 0 at " +
                 std::to_string(negative[i].size()) + " of " + std::to_string(h.clock[i].size()) +
                 " taus (" + taus_text(negative[i]) +
                 "): dev there is -sqrt(|variance|), without an interval; the clock is quieter "
                 "than the other two resolve, or the clocks are correlated";
  }
  return h;
}

std::size_t hat_pair_index(std::size_t i, std::size_t j, std::size_t n_clocks) {
  // Pairs (0, 1..N-1) come first, then (1, 2..N-1), ...: i full rows of N-1, N-2, ... before.
  return i * n_clocks - i * (i + 1) / 2 + (j - i - 1);
}

std::vector<double> hat_weights(std::size_t clock, std::size_t n_clocks) {
  const double n = static_cast<double>(n_clocks);
  std::vector<double> w;
  for (std::size_t i = 0; i < n_clocks; ++i)
    for (std::size_t j = i + 1; j < n_clocks; ++j)
      w.push_back(((i == clock || j == clock ? 1.0 : 0.0) - 1.0 / (n - 1.0)) / (n - 2.0));
  return w;
}

double n_hat_estimate_variance(std::span<const double> s, std::span<const double> nu,
                               std::span<const double> v, std::size_t clock, std::size_t n_clocks) {
  const std::vector<double> w = hat_weights(clock, n_clocks);
  struct Pair {
    std::size_t a, b;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < n_clocks; ++i)
    for (std::size_t j = i + 1; j < n_clocks; ++j)
      pairs.push_back({i, j});
  double var = 0.0;
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (std::size_t q = 0; q < pairs.size(); ++q) {
      double cov = 0.0;
      if (p == q) {
        cov = 2.0 * s[p] * s[p] / nu[p];
      } else {
        const Pair x = pairs[p], y = pairs[q];
        const bool share_a = x.a == y.a || x.a == y.b, share_b = x.b == y.a || x.b == y.b;
        if (share_a || share_b) {
          const double shared = v[share_a ? x.a : x.b];
          cov = 2.0 * shared * shared / std::sqrt(nu[p] * nu[q]);
        }
      }
      var += w[p] * w[q] * cov;
    }
  return var;
}

namespace {

void check_n_hat(std::span<const PhaseData> pairs, std::size_t n_clocks) {
  if (n_clocks < 3)
    throw std::invalid_argument("N-cornered hat: needs at least 3 clocks, got " +
                                std::to_string(n_clocks));
  if (pairs.size() != n_clocks * (n_clocks - 1) / 2)
    throw std::invalid_argument("N-cornered hat: " + std::to_string(n_clocks) + " clocks need " +
                                std::to_string(n_clocks * (n_clocks - 1) / 2) +
                                " pair records, got " + std::to_string(pairs.size()));
  for (std::size_t p = 1; p < pairs.size(); ++p)
    check_pair(pairs[0], pairs[p], "N-cornered hat: pair 1 and pair " + std::to_string(p + 1));
}

}  // namespace

NHatResult n_cornered_hat(std::span<const PhaseData> pairs, std::size_t n_clocks,
                          std::span<const std::int64_t> m_list, double confidence, int nthreads) {
  check_n_hat(pairs, n_clocks);
  check_confidence(confidence);
  const std::vector<std::int64_t> ms = oadev_ms(m_list, pairs[0].n_points());
  const std::size_t np = pairs.size();
  NHatResult h;
  for (const PhaseData& p : pairs)
    h.pair.push_back(oadev_with_confidence(p, ms, confidence, nthreads));
  h.clock.resize(n_clocks);
  h.notes.resize(n_clocks);
  std::vector<std::vector<double>> weights(n_clocks), negative(n_clocks);
  for (std::size_t k = 0; k < n_clocks; ++k)
    weights[k] = hat_weights(k, n_clocks);
  for (std::size_t i0 = 0; i0 < h.pair[0].size(); ++i0) {
    const std::int64_t m = h.pair[0].m[i0];
    std::vector<std::size_t> row(np);
    std::vector<double> s(np), nu(np), v(n_clocks, 0.0);
    std::int64_t n = h.pair[0].n[i0];
    bool complete = true;
    for (std::size_t p = 0; p < np && complete; ++p) {
      row[p] = row_of(h.pair[p], m);
      complete = row[p] < h.pair[p].size();
      if (!complete) break;
      s[p] = variance(h.pair[p], row[p]);
      nu[p] = h.pair[p].edf[row[p]];
      n = std::min(n, h.pair[p].n[row[p]]);
    }
    if (!complete) continue;
    for (std::size_t k = 0; k < n_clocks; ++k)
      for (std::size_t p = 0; p < np; ++p)
        v[k] += weights[k][p] * s[p];
    for (std::size_t k = 0; k < n_clocks; ++k) {
      const double var_v = n_hat_estimate_variance(s, nu, v, k, n_clocks);
      const double edf = v[k] > 0.0 && var_v > 0.0 ? 2.0 * v[k] * v[k] / var_v : kNaN;
      int alpha = std::numeric_limits<int>::max();
      for (std::size_t j = 0; j < n_clocks; ++j)
        if (j != k) {
          const std::size_t p = hat_pair_index(std::min(j, k), std::max(j, k), n_clocks);
          alpha = std::min(alpha, h.pair[p].alpha[row[p]]);
        }
      push_row(h.clock[k], m, h.pair[0].tau_s[i0], n, alpha, v[k], edf, confidence, false);
      if (!(v[k] > 0.0)) negative[k].push_back(h.pair[0].tau_s[i0]);
    }
  }
  for (std::size_t k = 0; k < n_clocks; ++k) {
    h.clock[k].confidence = confidence;
    if (negative[k].empty()) continue;
    h.notes[k] = "variance estimate <= 0 at " + std::to_string(negative[k].size()) + " of " +
                 std::to_string(h.clock[k].size()) + " taus (" + taus_text(negative[k]) +
                 "): dev there is -sqrt(|variance|), without an interval; the clock is quieter "
                 "than the others resolve, or the clocks are correlated";
  }
  return h;
}

CodevResult gcodev_with_confidence(const PhaseData& x, const PhaseData& y,
                                   std::span<const std::int64_t> m_list, double confidence,
                                   int nthreads) {
  check_pair(x, y, "gcodev");
  check_confidence(confidence);
  const std::vector<std::int64_t> ms = oadev_ms(m_list, x.n_points());
  CodevResult out;
  out.oadev[0] = oadev_with_confidence(x, ms, confidence, nthreads);
  out.oadev[1] = oadev_with_confidence(y, ms, confidence, nthreads);
  const StatResult g = gcodev(x, y, ms, nthreads);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const std::size_t rx = row_of(out.oadev[0], g.m[i]), ry = row_of(out.oadev[1], g.m[i]);
    // A gcodev term needs both records clean, so each record's OADEV has the row too.
    if (rx == out.oadev[0].size() || ry == out.oadev[1].size()) continue;
    const double v = std::copysign(g.dev[i] * g.dev[i], g.dev[i]);
    const double edf = codev_edf(variance(out.oadev[0], rx), variance(out.oadev[1], ry), v,
                                 out.oadev[0].edf[rx], out.oadev[1].edf[ry]);
    const int alpha = std::min(out.oadev[0].alpha[rx], out.oadev[1].alpha[ry]);
    push_row(out.codev, g.m[i], g.tau_s[i], g.n[i], alpha, v, edf, confidence, true);
  }
  out.codev.confidence = confidence;
  return out;
}

}  // namespace allanlot::kernels
