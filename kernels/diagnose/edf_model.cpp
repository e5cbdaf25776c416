// The edf of the overlapping Allan variance under the model being tested (docs/diagnose.md
// "Where"): from the model's own mix of power laws and effects, never from the measured curve's
// noise identification, and never above what the number of averages allows.
#include "kernels/diagnose/internal.hpp"

#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace diagnose_detail {
namespace {

constexpr FiniteDifferenceKind kOavar{2, true, false};

// The power law each eq. (3) term is (S_y ~ f^alpha): quantization is white PM (alpha 2),
// white FM 0, flicker FM -1, random walk FM -2; the ramp is deterministic (no alpha).
int term_alpha(Term t) {
  switch (t) {
  case Term::Q:
    return 2;
  case Term::N:
    return 0;
  case Term::B:
    return -1;
  case Term::K:
    return -2;
  default:
    return 0;
  }
}

// edf of a noise with a non-integer alpha in [-2, 0]: log-linear between the neighbouring
// integer power laws (the edf varies smoothly and monotonically in alpha at fixed m and N,
// Greenhall & Riley 2003, Fig. 1-3).
double edf_at_alpha(const Curve& cv, std::size_t i, double alpha) {
  const double a = std::clamp(alpha, -2.0, 2.0);
  const int lo = std::min(static_cast<int>(std::floor(a)), 1);
  const double w = a - lo;
  const double e_lo = cv.edf_pl[static_cast<std::size_t>(lo + 2)][i];
  const double e_hi = cv.edf_pl[static_cast<std::size_t>(lo + 3)][i];
  return std::exp((1.0 - w) * std::log(e_lo) + w * std::log(e_hi));
}

// The local power law of a Gauss-Markov effect at tau: its Allan variance goes as tau^mu
// with mu = +1 (random walk, alpha -2) for tau << tau_c and -1 (white FM, alpha 0) for
// tau >> tau_c, so alpha = -mu - 1 from the logarithmic slope at tau (IEEE Std 952-1997,
// annex C, the form of model_avar).
double markov_alpha(double tau_c, double tau) {
  ChannelSpec s;
  s.markovs.push_back({1.0, tau_c});
  const double h = 0.05;
  const double mu =
      (std::log(model_avar(s, tau * std::exp(h))) - std::log(model_avar(s, tau * std::exp(-h)))) /
      (2.0 * h);
  return std::clamp(-mu - 1.0, -2.0, 0.0);
}

// A resonance's edf at tau: its Allan variance is a variance of narrowband noise, which a
// record of T seconds holds about 2 B T independent pieces of, B = pi f0 / q its equivalent
// noise bandwidth (a Lorentzian's, pi times its half-power width f0 / q; Bendat & Piersol,
// Random Data, 4th ed., sec. 8.2.2: a mean square's normalized random error is 1 / sqrt(B T)).
// Beyond the coherence time the averages decorrelate the process into white FM, whose edf is
// the smaller one there; the smaller of the two is taken at every tau. A wandering resonance's
// bandwidth adds its Gaussian's, 2 sqrt(pi) spread_hz ((int S)^2 / int S^2 of a normal density).
double resonance_edf(const Resonance& r, const Curve& cv, std::size_t i) {
  const double t_record = static_cast<double>(cv.n_samples) * cv.tau0;
  const double bandwidth =
      std::numbers::pi * r.frequency_hz / r.q + 2.0 * std::sqrt(std::numbers::pi) * r.spread_hz;
  const double narrowband = 2.0 * bandwidth * t_record;
  return std::min(narrowband, cv.edf_pl[2][i]);
}

// A wandering resonance's Allan variance at a tau is its average over the frequencies the record
// visits: about n = T / (2 wander_s) independent draws of f0 (at least one), whose spread of
// avar_f(tau) about the mixture's mean a adds the relative variance var_f / (n a^2) to the
// estimate's (the ripples' positions move with f0, so at the taus of a ripple this can exceed the
// narrowband term many times). 0 for a stationary resonance.
double wander_variance(const Resonance& r, double rate_hz, const Curve& cv, std::size_t i,
                       double a) {
  if (!(r.spread_hz > 0.0) || !(a > 0.0)) return 0.0;
  const double t_record = static_cast<double>(cv.n_samples) * cv.tau0;
  const double n = std::max(1.0, t_record / (2.0 * r.wander_s));
  double var = 0.0;
  for (const auto& [node, w] : resonance_nodes(r)) {
    const double d = resonance_avar(node, rate_hz, static_cast<double>(cv.m[i])) - a;
    var += w * d * d;
  }
  return var / (n * a * a);
}

}  // namespace

void prepare_edf(Curve& cv) {
  const std::int64_t n_phase = cv.n_samples + 1;
  for (int alpha = -2; alpha <= 2; ++alpha) {
    auto& e = cv.edf_pl[static_cast<std::size_t>(alpha + 2)];
    e.resize(cv.size());
    for (std::size_t i = 0; i < cv.size(); ++i)
      e[i] = edf_greenhall(alpha, kOavar, cv.m[i], n_phase);
  }
  cv.edf_cap.resize(cv.size());
  for (std::size_t i = 0; i < cv.size(); ++i) {
    double cap = 0.0;
    for (const auto& e : cv.edf_pl)
      cap = std::max(cap, e[i]);
    cv.edf_cap[i] = cap;
  }
}

// Combination, per tau, of the model's components with Allan variances a_k:
//  - stochastic components (the four noise terms, Gauss-Markov) each have the Greenhall-Riley
//    edf e_k of their power law (a resonance its narrowband edf, resonance_edf, and a wandering
//    one the variance of its average over the wander, wander_variance), i.e.
//    sd(avar_hat_k) = a_k sqrt(2 / e_k). The estimate of their sum is a quadratic form in the sum
//    of their phases; its variance is 2 sum_kl tr(A R_k A R_l) with every cross term between 0 and
//    the geometric mean of the diagonal ones (Cauchy-Schwarz for positive semidefinite R_k), so the
//    standard deviations add at most linearly: sd_n <= sum_k a_k sqrt(2 / e_k), equality when the
//    spectra are alike (two white noises are one white noise, whose edf this returns exactly). The
//    upper bound of the variance is used: the edf is never overstated.
//  - deterministic components (ramp, sinusoids; steps are removed from the record) of total
//    a_d add no variance of their own but a cross term with the noise: 2/M sum_j c_j e_j, of
//    variance about 4 a_d a_n / e_n for second differences c_j that vary over the noise's
//    correlation length. Hence
//    edf = 2 (a_n + a_d)^2 / (2 a_n^2 / e_n + 4 a_d a_n / e_n)
//        = e_n (a_n + a_d)^2 / (a_n (a_n + 2 a_d)).
//  - the result is at most the largest edf any power-law noise reaches at that m and N (white
//    PM's, at the longest taus about the number of averages): however dominant a deterministic
//    effect, the estimate averages no more terms than the record holds.
std::vector<double> model_edf(const ChannelSpec& s, const Curve& cv, const Bases& raw) {
  const Bases b = s.lowpass.active() ? filtered_bases(raw, cv, s.lowpass) : raw;
  std::vector<double> out(cv.size());
  ChannelSpec det;
  det.rate_hz = s.rate_hz;
  det.sinusoids = s.sinusoids;
  det.terms.R = s.terms.R;
  for (std::size_t i = 0; i < cv.size(); ++i) {
    double a_n = 0.0, sd_n = 0.0;
    for (const Term t : all_terms()) {
      const double c = coefficient(s.terms, t);
      if (t == Term::R || !(c > 0.0)) continue;
      const double a = c * c * b.term[static_cast<std::size_t>(t)][i];
      a_n += a;
      sd_n += a * std::sqrt(2.0 / cv.edf_pl[static_cast<std::size_t>(term_alpha(t) + 2)][i]);
    }
    if (s.quantum > 0.0) {  // the output's rounding: white FM of quantum^2 / 12 per sample
      const double a = s.quantum * s.quantum / (12.0 * static_cast<double>(cv.m[i]));
      a_n += a;
      sd_n += a * std::sqrt(2.0 / cv.edf_pl[2][i]);
    }
    for (const GaussMarkov& g : s.markovs) {
      if (!(g.sigma > 0.0)) continue;
      ChannelSpec one;
      one.markovs.push_back(g);
      const double a = model_avar(one, cv.tau[i]);
      a_n += a;
      sd_n += a * std::sqrt(2.0 / edf_at_alpha(cv, i, markov_alpha(g.tau_c_s, cv.tau[i])));
    }
    for (const Resonance& r : s.resonances) {
      if (!(r.sigma > 0.0)) continue;
      const double a = resonance_avar(r, s.rate_hz, static_cast<double>(cv.m[i]));
      a_n += a;
      sd_n +=
          a * std::sqrt(2.0 / resonance_edf(r, cv, i) + wander_variance(r, s.rate_hz, cv, i, a));
    }
    const double a_d = model_avar(det, cv.tau[i]);
    double edf = cv.edf_cap[i];
    if (a_n > 0.0 && sd_n > 0.0) {
      const double e_n = 2.0 * a_n * a_n / (sd_n * sd_n);
      edf = std::min(edf, e_n * (a_n + a_d) * (a_n + a_d) / (a_n * (a_n + 2.0 * a_d)));
    }
    out[i] = edf;
  }
  return out;
}

void use_edf(Curve& cv, std::vector<double> edf) {
  if (edf.size() != cv.size()) throw std::logic_error("diagnose: edf of the wrong length");
  cv.edf = std::move(edf);
  cv.ln_y.resize(cv.size());
  cv.var_ln.resize(cv.size());
  for (std::size_t i = 0; i < cv.size(); ++i) {
    const double half = 0.5 * cv.edf[i];
    cv.ln_y[i] = std::log(cv.y[i]) - (digamma(half) - std::log(half));
    cv.var_ln[i] = trigamma(half);
  }
}

}  // namespace diagnose_detail

std::vector<double> diagnose_model_edf(const ChannelSpec& model, std::span<const std::int64_t> m,
                                       std::int64_t n_samples) {
  using namespace diagnose_detail;
  validate(model);
  Curve cv;
  cv.tau0 = 1.0 / model.rate_hz;
  cv.n_samples = n_samples;
  for (const std::int64_t mi : m) {
    if (mi < 1 || greenhall_terms(kOavar, mi, n_samples + 1) < 1)
      throw std::invalid_argument("diagnose_model_edf: m = " + std::to_string(mi) +
                                  " has no term in " + std::to_string(n_samples) + " samples");
    cv.m.push_back(mi);
    cv.tau.push_back(static_cast<double>(mi) * cv.tau0);
  }
  prepare_edf(cv);
  return model_edf(model, cv, make_bases(cv, model.rate_hz, model.quantum));
}

}  // namespace allanlot::kernels
