// A resonance's process, Allan variance and PSD: see resonance.hpp.
#include "kernels/simulate/resonance.hpp"

#include "kernels/simulate/lowpass.hpp"
#include "kernels/simulate/rng.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace allanlot::kernels {

namespace {

using cplx = std::complex<double>;

// The AR(2) of resonance.hpp: its pole z, the autocovariance's constant c, the recursion's
// coefficients and the innovation's sd; and e^L - 1 and g(L) of L = ln z, which every D(k) uses.
struct Ar2 {
  cplx z, log_z, c, z_minus_1, g_log_z;
  double a1 = 0, a2 = 0, rho1 = 0, sd_e = 0, sigma = 0;
};

cplx g_of(cplx x);

Ar2 ar2_of(const Resonance& r, double rate_hz) {
  const double theta = 2.0 * std::numbers::pi * r.frequency_hz / rate_hz;
  const double ln_r = -0.5 * theta / r.q;  // r = exp(-pi f0 h / q)
  Ar2 p;
  p.sigma = r.sigma;
  p.log_z = {ln_r, theta};
  p.z = std::exp(p.log_z);
  const double rr = std::exp(ln_r);
  p.a1 = 2.0 * rr * std::cos(theta);
  p.a2 = -rr * rr;
  p.rho1 = p.a1 / (1.0 - p.a2);
  const double b = (p.rho1 / rr - std::cos(theta)) / std::sin(theta);
  p.c = r.sigma * r.sigma * cplx(1.0, -b);
  const double rho2 = p.a1 * p.rho1 + p.a2;
  p.sd_e = r.sigma * std::sqrt(std::max(0.0, 1.0 - p.a1 * p.rho1 - p.a2 * rho2));
  p.z_minus_1 = std::exp(p.log_z) - 1.0;
  p.g_log_z = g_of(p.log_z);
  return p;
}

// g(x) = e^x - 1 - x, by its series where the closed form would cancel (terms fall by |x| / n:
// below 1e-17 relative by n = 22 for |x| < 0.5).
cplx g_of(cplx x) {
  if (std::abs(x) >= 0.5) return std::exp(x) - 1.0 - x;
  cplx term = x * x / 2.0, sum = 0.0;
  for (int n = 2; n <= 24; ++n) {
    sum += term;
    term *= x / static_cast<double>(n + 1);
  }
  return sum;
}

// D(k), the variance of a sum of k consecutive samples (resonance.hpp): with L = ln z,
// z^(k+1) - (k+1) z + k = g((k+1) L) - (k+1) g(L) and (1 - z)^2 = (e^L - 1)^2.
double sum_var(const Ar2& p, double k) {
  if (k <= 0.0) return 0.0;
  const cplx num = g_of((k + 1.0) * p.log_z) - (k + 1.0) * p.g_log_z;
  return std::real(p.c * (2.0 * num / (p.z_minus_1 * p.z_minus_1) - k));
}

}  // namespace

std::vector<std::pair<Resonance, double>> resonance_nodes(const Resonance& r) {
  Resonance node = r;
  node.spread_hz = 0.0;
  if (!(r.spread_hz > 0.0)) return {{node, 1.0}};
  // The node spacing in standard deviations: a Lorentzian narrower than the spread needs nodes
  // closer than its width, or the mixture's PSD would show the nodes as separate peaks.
  const double step = std::min(0.5, r.frequency_hz / (2.0 * r.q) / r.spread_hz);
  const int half = std::min(64, static_cast<int>(std::ceil(4.0 / step)));
  std::vector<std::pair<Resonance, double>> out;
  double total = 0.0;
  for (int i = -half; i <= half; ++i) {
    const double u = 4.0 * i / half;
    node.frequency_hz = r.frequency_hz + r.spread_hz * u;
    const double w = std::exp(-0.5 * u * u) * (std::abs(i) == half ? 0.5 : 1.0);
    out.emplace_back(node, w);
    total += w;
  }
  for (auto& nw : out)
    nw.second /= total;
  return out;
}

std::vector<double> resonance_autocovariance(const Resonance& r, double rate_hz,
                                             std::size_t n_lags) {
  std::vector<double> c(n_lags, 0.0);
  for (const auto& [node, w] : resonance_nodes(r)) {
    const Ar2 p = ar2_of(node, rate_hz);
    for (std::size_t k = 0; k < n_lags; ++k)
      c[k] += w * std::real(p.c * std::exp(static_cast<double>(k) * p.log_z));
  }
  return c;
}

namespace {

// The Allan variance of one resonance under one filter at many m. For k >= 0,
// D(k) = Re[alpha z^k] + beta k + gamma with alpha = 2 c z / (1 - z)^2,
// beta = Re[c (2 / (1 - z) - 1)], gamma = -Re[alpha] (the closed form of resonance.hpp split into
// its geometric and linear parts), so where every |o - j| of F(o) = sum_j rho_|j| D(|o - j|) is
// o - j >= 0,
//   F(o) = Re[alpha z^o R] + (beta o + gamma) S,  R = sum_j rho_|j| z^-j,  S = sum_j rho_|j|,
// one complex exponential instead of 2 J + 1 structure functions. Below o |ln z| = 0.5 the two
// parts cancel (each of order 1 / |1 - z|^2 where D is of order k^2) and F is summed directly.
class AvarUnderFilter {
public:
  AvarUnderFilter(const Resonance& r, double rate_hz, const std::vector<double>& rho)
      : p_(ar2_of(r, rate_hz)), rho_(rho) {
    const cplx one_m_z = 1.0 - p_.z;
    alpha_ = 2.0 * p_.c * p_.z / (one_m_z * one_m_z);
    beta_ = std::real(p_.c * (2.0 / one_m_z - 1.0));
    gamma_ = -std::real(alpha_);
    for (std::size_t j = 0; j < rho.size(); ++j) {
      const double w = j == 0 ? 1.0 : 2.0;
      s_ += w * rho[j];
      const auto jd = static_cast<double>(j);
      r_ += rho[j] * (j == 0 ? cplx(1.0) : std::exp(-jd * p_.log_z) + std::exp(jd * p_.log_z));
    }
    o_closed_ = std::max(static_cast<double>(rho.size()) - 1.0, 0.5 / std::abs(p_.log_z));
    f0_ = direct(0.0);
  }

  double at(double m) const { return (8.0 * f(m) - 2.0 * f(2.0 * m) - 6.0 * f0_) / (4.0 * m * m); }

private:
  double direct(double o) const {
    return lowpass_structure_sum([this](double k) { return sum_var(p_, k); }, o, rho_);
  }
  double f(double o) const {
    if (o < o_closed_) return direct(o);
    return std::real(alpha_ * std::exp(o * p_.log_z) * r_) + (beta_ * o + gamma_) * s_;
  }

  Ar2 p_;
  const std::vector<double>& rho_;
  cplx alpha_, r_ = 0.0;
  double beta_ = 0, gamma_ = 0, s_ = 0, o_closed_ = 0, f0_ = 0;
};

}  // namespace

double resonance_avar(const Resonance& r, double rate_hz, double m,
                      const std::vector<double>& rho) {
  if (!(m > 0.0)) throw std::invalid_argument("resonance_avar: m must be > 0");
  double v = 0.0;
  for (const auto& [node, w] : resonance_nodes(r))
    v += w * AvarUnderFilter(node, rate_hz, rho).at(m);
  return v;
}

std::vector<double> resonance_avar(const Resonance& r, double rate_hz,
                                   std::span<const std::int64_t> m,
                                   const std::vector<double>& rho) {
  for (const std::int64_t mi : m)
    if (mi < 1) throw std::invalid_argument("resonance_avar: m must be >= 1");
  std::vector<double> out(m.size(), 0.0);
  for (const auto& [node, w] : resonance_nodes(r)) {
    const AvarUnderFilter a(node, rate_hz, rho);
    for (std::size_t i = 0; i < m.size(); ++i)
      out[i] += w * a.at(static_cast<double>(m[i]));
  }
  return out;
}

double resonance_psd_one_sided(const Resonance& r, double rate_hz, double f_hz) {
  double s = 0.0;
  add_resonance_psd(r, rate_hz, 1.0, std::span(&f_hz, 1), std::span(&s, 1));
  return s;
}

PsdTrig::PsdTrig(std::span<const double> f_hz, double rate_hz)
    : c1(f_hz.size()), s1(f_hz.size()), c2(f_hz.size()), s2(f_hz.size()) {
  for (std::size_t i = 0; i < f_hz.size(); ++i) {
    const double w = 2.0 * std::numbers::pi * f_hz[i] / rate_hz;
    c1[i] = std::cos(w);
    s1[i] = std::sin(w);
    c2[i] = std::cos(2.0 * w);
    s2[i] = std::sin(2.0 * w);
  }
}

// |1 - a1 e^-iw - a2 e^-2iw|^2 = (1 - a1 c1 - a2 c2)^2 + (a1 s1 + a2 s2)^2 with c_k = cos(k w),
// s_k = sin(k w): the trigonometry once per frequency, the nodes' coefficients once per node.
// The nodes are the outer loop and the frequencies the inner one, each frequency's sum over the
// nodes taken in node order as before (the same sum, bit for bit): the inner loop then has no
// dependence from one step to the next and runs as vector divisions, where a sum per frequency
// waited on each division in turn (a wandering resonance's Whittle fits, up to 129 nodes at every
// block of a peak's window, were a quarter of a modelled ADIS16405 accelerometer's time).
void add_resonance_psd(const Resonance& r, double rate_hz, double scale, const PsdTrig& trig,
                       std::span<double> out) {
  const std::size_t n = trig.size();
  std::vector<double> s(n, 0.0);
  const double* c1 = trig.c1.data();
  const double* c2 = trig.c2.data();
  const double* s1 = trig.s1.data();
  const double* s2 = trig.s2.data();
  double* acc = s.data();
  for (const auto& [node, weight] : resonance_nodes(r)) {
    const Ar2 p = ar2_of(node, rate_hz);
    const double a1 = p.a1, a2 = p.a2, gain = scale * weight * 2.0 * p.sd_e * p.sd_e / rate_hz;
    for (std::size_t i = 0; i < n; ++i) {
      const double re = 1.0 - a1 * c1[i] - a2 * c2[i], im = a1 * s1[i] + a2 * s2[i];
      acc[i] += gain / (re * re + im * im);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    out[i] += s[i];
}

void add_resonance_psd(const Resonance& r, double rate_hz, double scale,
                       std::span<const double> f_hz, std::span<double> out) {
  add_resonance_psd(r, rate_hz, scale, PsdTrig(f_hz, rate_hz), out);
}

// x_0 and x_1 from the stationary law (unit variances, correlation rho1), then the recursion,
// two samples to each pair of normals. A wandering resonance's coefficients are those of the
// frequency f0 + spread u: u starts in its stationary law and steps every kHold samples as a unit
// Gauss-Markov process sampled there (exactly: its correlation over kHold samples is phi), its
// normals the same sequence's from pair 2^55 on; a stationary one keeps u = 0.
void add_resonance(const Resonance& r, double rate_hz, std::uint64_t seed, std::uint64_t stream,
                   std::uint32_t component, std::span<double> y) {
  if (y.empty() || !(r.sigma > 0.0)) return;
  constexpr std::uint64_t kWanderIndex = std::uint64_t{1} << 55;
  constexpr std::size_t kHold = 8;  // even: the coefficients change on a pair's first sample
  const auto normal = [&](std::uint64_t k) {
    const auto pair = rng::normal_pair(seed, stream, component, k / 2);
    return k % 2 == 0 ? pair.first : pair.second;
  };
  const bool wanders = r.spread_hz > 0.0;
  const double phi = wanders ? std::exp(-static_cast<double>(kHold) / (rate_hz * r.wander_s)) : 0.0;
  const auto at = [&](double u) {
    return ar2_of({r.sigma, r.frequency_hz + r.spread_hz * std::clamp(u, -4.0, 4.0), r.q}, rate_hz);
  };
  double u = wanders ? normal(2 * kWanderIndex) : 0.0;
  Ar2 p = at(u);
  double x2 = p.sigma * normal(0);
  y[0] += x2;
  if (y.size() == 1) return;
  double x1 = p.rho1 * x2 + p.sigma * std::sqrt(1.0 - p.rho1 * p.rho1) * normal(1);
  y[1] += x1;
  for (std::size_t k = 2; k < y.size(); k += 2) {
    if (wanders && k % kHold == 0) {
      u = phi * u + std::sqrt(1.0 - phi * phi) * normal(2 * kWanderIndex + k / kHold);
      p = at(u);
    }
    const auto [g0, g1] = rng::normal_pair(seed, stream, component, k / 2);
    const double x0 = p.a1 * x1 + p.a2 * x2 + p.sd_e * g0;
    y[k] += x0;
    x2 = x1;
    x1 = x0;
    if (k + 1 == y.size()) break;
    const double xn = p.a1 * x1 + p.a2 * x2 + p.sd_e * g1;
    y[k + 1] += xn;
    x2 = x1;
    x1 = xn;
  }
}

void add_effect_record(const Resonance& r, double rate_hz, std::uint64_t seed, std::uint64_t stream,
                       std::uint32_t component, std::span<double> y) {
  add_resonance(r, rate_hz, seed, stream, component, y);
}

double effect_avar(const Resonance& r, double rate_hz, double tau) {
  return resonance_avar(r, rate_hz, tau * rate_hz);
}

double filter_change_avar(const Resonance& r, const FilterAt& at) {
  const auto md = static_cast<double>(at.m);
  return resonance_avar(r, at.rate_hz, md, at.rho()) - resonance_avar(r, at.rate_hz, md);
}

void add_effect_psd(const Resonance& r, double rate_hz, std::span<const double> f_hz,
                    std::vector<double>& out) {
  add_resonance_psd(r, rate_hz, 1.0, f_hz, out);
}

}  // namespace allanlot::kernels
