#include "kernels/diagnose/diagnose.hpp"

#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/least_squares.hpp"
#include "kernels/common/parallel.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/spectral/psd.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace allanlot::kernels {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The measured curve on the comparison grid with the exact moments of its logarithm:
// for edf * avar_hat / avar ~ chi2_nu, E ln(avar_hat / avar) = psi(nu/2) - ln(nu/2) (about
// -1/nu) and var = psi'(nu/2) (about 2/nu), so ln_y below is unbiased for ln avar and var_ln its
// variance; at edf ~ 3 the bias is -0.37 and the variance 1.4 times 2/nu, which matters for the
// longest taus.
struct Curve {
  std::vector<std::int64_t> m, n;
  std::vector<double> tau, y, edf, ln_y, var_ln;
  double tau0 = 1.0;
  std::int64_t n_samples = 0;
  std::size_t size() const { return m.size(); }
};

// A model component: an eq. (3) term, a sinusoid or a Gauss-Markov effect. `coef` is the
// model file's coefficient (R..Q, amplitude, sigma); the avar is coef^2 times a basis curve.
enum class Kind { Term, Sinusoid, Markov };
struct Component {
  Kind kind = Kind::Term;
  Term term = Term::N;
  double nl = 0.0;     // frequency_hz (sinusoid) or tau_c_s (markov)
  double phase = 0.0;  // sinusoid phase (no effect on avar; kept for the model file)
  double coef = 0.0;
  bool free = false;       // re-estimated by the fit
  bool nl_free = false;    // tau_c is searched (for its uncertainty)
  bool given = false;      // part of the given model
  double nl_sigma = kNaN;  // uncertainty of nl when it comes from elsewhere (the PSD)
  // An added sinusoid's amplitude comes from the PSD line and is never refitted on the Allan
  // curve: there its bump overlaps any hump nearby (a Gauss-Markov effect at a similar tau),
  // which the amplitude would absorb, whereas the line's power above the local background is
  // the sinusoid's alone.
  bool pinned = false;
  double coef_sigma = kNaN;  // uncertainty of coef when pinned
};

// Basis curves: the avar of each component with unit coefficient, from model_avar_sampled so
// that the diagnosis uses exactly the theory the simulator is tested against. The five term
// bases are computed once (flicker's sampling factor is a quadrature).
struct Bases {
  std::array<std::vector<double>, kNumTerms> term;
  double rate_hz = 1.0;
};

std::vector<double> basis_of(const Component& c, const Curve& cv, const Bases& b) {
  if (c.kind == Kind::Term) return b.term[static_cast<std::size_t>(c.term)];
  ChannelSpec s;
  s.rate_hz = b.rate_hz;
  if (c.kind == Kind::Sinusoid)
    s.sinusoids.push_back({1.0, c.nl, 0.0});
  else
    s.markovs.push_back({1.0, c.nl});
  // model_avar, not model_avar_sampled: both are exact for these components at every m, and
  // the sampled form would evaluate flicker's quadrature factor for nothing.
  std::vector<double> g(cv.size());
  for (std::size_t i = 0; i < cv.size(); ++i)
    g[i] = model_avar(s, cv.tau[i]);
  return g;
}

Bases make_bases(const Curve& cv, double rate_hz) {
  Bases b;
  b.rate_hz = rate_hz;
  for (const Term t : all_terms()) {
    ChannelSpec s;
    s.rate_hz = rate_hz;
    coefficient(s.terms, t) = 1.0;
    auto& g = b.term[static_cast<std::size_t>(t)];
    g.resize(cv.size());
    for (std::size_t i = 0; i < cv.size(); ++i)
      g[i] = model_avar_sampled(s, cv.m[i]);
  }
  return b;
}

std::vector<Component> components_of(const ChannelSpec& s) {
  std::vector<Component> out;
  for (const Term t : all_terms())
    if (coefficient(s.terms, t) > 0.0) {
      Component c;
      c.term = t;
      c.coef = coefficient(s.terms, t);
      c.given = true;
      out.push_back(c);
    }
  for (const Sinusoid& q : s.sinusoids) {
    Component c;
    c.kind = Kind::Sinusoid;
    c.nl = q.frequency_hz;
    c.phase = q.phase_rad;
    c.coef = q.amplitude;
    c.given = true;
    out.push_back(c);
  }
  for (const GaussMarkov& g : s.markovs) {
    Component c;
    c.kind = Kind::Markov;
    c.nl = g.tau_c_s;
    c.coef = g.sigma;
    c.given = true;
    out.push_back(c);
  }
  return out;
}

ChannelSpec spec_of(const std::vector<Component>& comps, const ChannelSpec& like) {
  ChannelSpec s;
  s.rate_hz = like.rate_hz;
  s.offset = like.offset;
  for (const Component& c : comps) {
    if (c.kind == Kind::Term) {
      coefficient(s.terms, c.term) = c.coef;
    } else if (c.kind == Kind::Sinusoid) {
      s.sinusoids.push_back({c.coef, c.nl, c.phase});
    } else {
      s.markovs.push_back({c.coef, c.nl});
    }
  }
  return s;
}

// Diagnose's choices for the one NNLS (kernels/model/least_squares.hpp): a tolerance of
// 1e-12 |A| max(1, |b|), at most 3 k + 3 additions and k + 1 steps each for k columns, a
// coefficient at or below 1e-300 leaves the active set. Its results were validated with these
// (docs/diagnose.md's studies), so they stay.
constexpr detail::NnlsOptions kComponentNnls{1e-12, 1.0, 3, 3, 1, 1, 1e-300, false, false};

// A fitted set of components.
struct Fit {
  std::vector<Component> comps;
  std::vector<double> model;  // avar of the components at each tau
  double chi2 = 0.0;          // sum (ln_y - ln model)^2 / var_ln
};

double log_chi2(const Curve& cv, const std::vector<double>& model) {
  double s = 0.0;
  for (std::size_t i = 0; i < cv.size(); ++i) {
    const double r = cv.ln_y[i] - std::log(std::max(model[i], 1e-300));
    s += r * r / cv.var_ln[i];
  }
  return s;
}

// Fits the squared coefficients of the free components (the others fixed), as kernels/model/fit.hpp
// does for eq. (3): non-negative weighted least squares on the variances with weights
// 1 / var(avar_hat) = 1 / (var_ln avar_model^2), reweighted from the model until it settles.
// Weights from the model rather than the estimate avoid favouring estimates that fell low. To
// first order this minimizes the chi-square of the log residuals that the criterion uses.
Fit fit_components(std::vector<Component> comps, const Curve& cv, const Bases& b) {
  const std::size_t p = cv.size();
  std::vector<std::vector<double>> g;
  std::vector<std::size_t> free_idx;
  std::vector<double> fixed(p, 0.0);
  for (std::size_t c = 0; c < comps.size(); ++c) {
    std::vector<double> gc = basis_of(comps[c], cv, b);
    if (comps[c].free) {
      free_idx.push_back(c);
      g.push_back(std::move(gc));
    } else {
      for (std::size_t i = 0; i < p; ++i)
        fixed[i] += comps[c].coef * comps[c].coef * gc[i];
    }
  }
  std::vector<double> model(p);
  for (std::size_t i = 0; i < p; ++i)
    model[i] = free_idx.empty() ? fixed[i] : cv.y[i];
  const auto k = static_cast<Eigen::Index>(free_idx.size());
  if (k > 0) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(p), k);
    Eigen::VectorXd rhs(static_cast<Eigen::Index>(p));
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(k);
    for (int it = 0; it < 60; ++it) {
      for (std::size_t i = 0; i < p; ++i) {
        const double sw = 1.0 / (std::sqrt(cv.var_ln[i]) * std::max(model[i], 1e-300));
        rhs(static_cast<Eigen::Index>(i)) = sw * (cv.y[i] - fixed[i]);
        for (Eigen::Index j = 0; j < k; ++j)
          a(static_cast<Eigen::Index>(i), j) = sw * g[static_cast<std::size_t>(j)][i];
      }
      // Columns scaled to unit norm: the regressors span many decades (tau^2 against
      // 1/tau^2), which would otherwise decide the pivoting and the NNLS tolerance.
      Eigen::VectorXd scale(k);
      for (Eigen::Index j = 0; j < k; ++j) {
        scale(j) = a.col(j).norm();
        if (!(scale(j) > 0.0)) scale(j) = 1.0;
        a.col(j) /= scale(j);
      }
      theta = detail::nnls(a, rhs, kComponentNnls).cwiseQuotient(scale);
      double change = 0.0;
      for (std::size_t i = 0; i < p; ++i) {
        double v = fixed[i];
        for (Eigen::Index j = 0; j < k; ++j)
          v += theta(j) * g[static_cast<std::size_t>(j)][i];
        change = std::max(change, std::abs(v - model[i]) / std::max(std::abs(model[i]), 1e-300));
        model[i] = v;
      }
      if (change < 1e-10) break;
    }
    for (Eigen::Index j = 0; j < k; ++j)
      comps[free_idx[static_cast<std::size_t>(j)]].coef = std::sqrt(std::max(theta(j), 0.0));
  }
  Fit f;
  f.comps = std::move(comps);
  f.model = std::move(model);
  f.chi2 = log_chi2(cv, f.model);
  return f;
}

// Uncertainties of the free parameters of a fit, from the log-space Fisher information
// F = J^T diag(1 / var_ln) J with J_ij = d ln avar_model_i / d p_j (p: the coefficients
// themselves, and tau_c where it was searched), inflated by P / n_eff because the P estimates
// carry only about n_eff independent pieces of information (see the header). Parameters held
// at zero get NaN (their uncertainty is not a Gaussian one).
void fill_sigmas(Fit& f, const Curve& cv, const Bases& b, double n_eff,
                 std::vector<double>& coef_sigma, std::vector<double>& nl_sigma) {
  const std::size_t p = cv.size();
  coef_sigma.assign(f.comps.size(), kNaN);
  nl_sigma.assign(f.comps.size(), kNaN);
  std::vector<std::pair<std::size_t, bool>> params;  // (component, is nl)
  std::vector<std::vector<double>> cols;
  for (std::size_t c = 0; c < f.comps.size(); ++c) {
    const Component& comp = f.comps[c];
    if (!comp.free || !(comp.coef > 0.0)) continue;
    const std::vector<double> g = basis_of(comp, cv, b);
    std::vector<double> d(p);
    for (std::size_t i = 0; i < p; ++i)
      d[i] = 2.0 * comp.coef * g[i] / f.model[i];
    params.emplace_back(c, false);
    cols.push_back(std::move(d));
    if (comp.nl_free) {
      const double h = 1e-4;
      Component lo = comp, hi = comp;
      lo.nl *= 1.0 - h;
      hi.nl *= 1.0 + h;
      const std::vector<double> gl = basis_of(lo, cv, b), gh = basis_of(hi, cv, b);
      std::vector<double> dn(p);
      for (std::size_t i = 0; i < p; ++i)
        dn[i] = comp.coef * comp.coef * (gh[i] - gl[i]) / (2.0 * h * comp.nl) / f.model[i];
      params.emplace_back(c, true);
      cols.push_back(std::move(dn));
    }
  }
  if (params.empty()) return;
  const auto k = static_cast<Eigen::Index>(params.size());
  Eigen::MatrixXd j(static_cast<Eigen::Index>(p), k);
  for (std::size_t i = 0; i < p; ++i)
    for (Eigen::Index q = 0; q < k; ++q)
      j(static_cast<Eigen::Index>(i), q) =
          cols[static_cast<std::size_t>(q)][i] / std::sqrt(cv.var_ln[i]);
  const Eigen::MatrixXd fisher = j.transpose() * j;
  const Eigen::MatrixXd cov =
      fisher.completeOrthogonalDecomposition().pseudoInverse() * (static_cast<double>(p) / n_eff);
  for (Eigen::Index q = 0; q < k; ++q) {
    const auto [c, is_nl] = params[static_cast<std::size_t>(q)];
    const double s = std::sqrt(std::max(cov(q, q), 0.0));
    (is_nl ? nl_sigma : coef_sigma)[c] = s;
  }
}

std::string term_key(Term t) {
  return std::string(term_name(t));
}

// The parameters of one component under the model file's keys.
std::vector<Parameter> parameters_of(const Component& c, double coef_sigma, double nl_sigma) {
  if (c.kind == Kind::Term) return {{term_key(c.term), c.coef, coef_sigma}};
  if (c.kind == Kind::Sinusoid)
    return {{"amplitude", c.coef, c.pinned ? c.coef_sigma : coef_sigma},
            {"frequency_hz", c.nl, std::isnan(c.nl_sigma) ? nl_sigma : c.nl_sigma}};
  return {{"sigma", c.coef, coef_sigma}, {"tau_c_s", c.nl, nl_sigma}};
}

std::string component_label(const std::vector<Component>& comps, std::size_t idx) {
  const Component& c = comps[idx];
  if (c.kind == Kind::Term) return term_key(c.term);
  int ordinal = 0;
  for (std::size_t i = 0; i < idx; ++i)
    ordinal += comps[i].kind == c.kind ? 1 : 0;
  return std::string(c.kind == Kind::Sinusoid ? "sinusoid[" : "markov[") + std::to_string(ordinal) +
         "]";
}

Comparison compare(const Curve& cv, std::vector<double> model, double alpha_tau) {
  Comparison out;
  const std::size_t p = cv.size();
  out.z.resize(p);
  out.p_value.resize(p);
  out.significant.resize(p);
  double s = 0.0;
  for (std::size_t i = 0; i < p; ++i) {
    const double ratio = cv.y[i] / model[i];
    out.z[i] = std::log(ratio) / std::sqrt(2.0 / cv.edf[i]);
    s += out.z[i] * out.z[i];
    const double cdf = chi2_cdf(cv.edf[i] * ratio, cv.edf[i]);
    out.p_value[i] = 2.0 * std::min(cdf, 1.0 - cdf);
    out.significant[i] = out.p_value[i] < alpha_tau ? 1 : 0;
  }
  out.gap = p ? std::sqrt(s / static_cast<double>(p)) : 0.0;
  for (std::size_t i = 0; i < p; ++i) {
    if (!out.significant[i]) continue;
    const int sign = out.z[i] > 0.0 ? 1 : -1;
    if (!out.bands.empty() && out.bands.back().last + 1 == i && out.bands.back().sign == sign) {
      out.bands.back().last = i;
      out.bands.back().tau_hi_s = cv.tau[i];
      out.bands.back().max_abs_z = std::max(out.bands.back().max_abs_z, std::abs(out.z[i]));
    } else {
      out.bands.push_back({i, i, cv.tau[i], cv.tau[i], sign, std::abs(out.z[i])});
    }
  }
  out.avar_model = std::move(model);
  return out;
}

// model_avar_sampled of spec `s` at the curve's taus, from the cached term bases.
std::vector<double> model_curve(const ChannelSpec& s, const Curve& cv, const Bases& b) {
  std::vector<double> v(cv.size());
  ChannelSpec effects = s;
  effects.terms = {};
  for (std::size_t i = 0; i < cv.size(); ++i) {
    v[i] = model_avar(effects, cv.tau[i]);
    for (const Term t : all_terms()) {
      const double c = coefficient(s.terms, t);
      v[i] += c * c * b.term[static_cast<std::size_t>(t)][i];
    }
    if (!(v[i] > 0.0) || !std::isfinite(v[i]))
      throw std::invalid_argument("diagnose: the model's Allan variance is " +
                                  std::to_string(v[i]) + " at tau = " + std::to_string(cv.tau[i]) +
                                  " s; a model must predict some noise at every tau");
  }
  return v;
}

// Linear-interpolation quantile of sorted values (Hyndman & Fan type 7, R's default).
double quantile_sorted(const std::vector<double>& v, double q) {
  if (v.empty()) return kNaN;
  const double h = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

McBand monte_carlo(const ChannelSpec& spec, const Curve& cv, const std::vector<double>& model,
                   int replicas, std::uint64_t seed, int threads) {
  McBand out;
  out.replicas = replicas;
  const std::size_t p = cv.size();
  if (replicas <= 0) return out;
  const auto n = static_cast<std::size_t>(cv.n_samples);
  std::vector<std::vector<double>> avar(static_cast<std::size_t>(replicas));
  ExceptionCollector errors;
  // One replica per iteration, each written by one thread into its own row, with its own
  // Philox stream (the replica index): the band does not depend on the thread count.
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (int r = 0; r < replicas; ++r) {
    errors.run([&] {
      std::vector<double> buf(n);
      simulate_channel(spec, seed, static_cast<std::uint64_t>(r), buf, 1);
      const PhaseData ph = phase_from_rate(buf, spec.rate_hz, 1);
      const StatResult s = compute(Stat::Oadev, ph, cv.m, 1);
      if (s.size() != p) throw std::logic_error("diagnose: replica tau grid differs");
      auto& row = avar[static_cast<std::size_t>(r)];
      row.resize(p);
      for (std::size_t i = 0; i < p; ++i)
        row[i] = s.dev[i] * s.dev[i];
    });
  }
  errors.rethrow();
  out.avar_lo.resize(p);
  out.avar_median.resize(p);
  out.avar_hi.resize(p);
  std::vector<double> col(static_cast<std::size_t>(replicas));
  for (std::size_t i = 0; i < p; ++i) {
    for (std::size_t r = 0; r < col.size(); ++r)
      col[r] = avar[r][i];
    std::sort(col.begin(), col.end());
    out.avar_lo[i] = quantile_sorted(col, 0.05);
    out.avar_median[i] = quantile_sorted(col, 0.5);
    out.avar_hi[i] = quantile_sorted(col, 0.95);
  }
  // The replicas' gaps use the measurement's edf, so that they are draws of the very statistic
  // reported for the measurement under the hypothesis that the model is right.
  for (const auto& row : avar)
    out.gaps.push_back(diagnose_gap(row, model, cv.edf));
  std::vector<double> g = out.gaps;
  std::sort(g.begin(), g.end());
  out.gap_median = quantile_sorted(g, 0.5);
  out.gap_p95 = quantile_sorted(g, 0.95);
  return out;
}

// Satterthwaite's effective number of independent taus from the model covariance of the
// estimates (see the header). The eq. (3) fit to the measurement supplies the covariance.
double effective_taus(const Curve& cv) {
  const std::size_t p = cv.size();
  Eq3Fit fit(p);
  FitInput in;
  in.tau_s = cv.tau;
  in.values = cv.y;
  in.n = cv.n;
  in.edf = cv.edf;
  in.tau0_s = cv.tau0;
  in.n_samples = cv.n_samples;
  const FitResult r = fit.fit(in);
  const Eigen::MatrixXd& s = fit.covariance();
  if (r.status == FitStatus::Ok && s.rows() == static_cast<Eigen::Index>(p) && s.allFinite()) {
    double sum = 0.0;
    bool ok = true;
    for (Eigen::Index i = 0; i < s.rows(); ++i)
      for (Eigen::Index j = 0; j < s.cols(); ++j) {
        const double d = s(i, i) * s(j, j);
        if (!(d > 0.0)) ok = false;
        const double c = ok ? s(i, j) / std::sqrt(d) : 0.0;
        sum += c * c;
      }
    if (ok && sum > 0.0)
      return std::clamp(static_cast<double>(p * p) / sum, 1.0, static_cast<double>(p));
  }
  // Fallback: one independent estimate per octave of tau (overlapping estimates an octave or
  // more apart are correlated well below 0.5 for the common noises).
  return std::clamp(std::log2(cv.tau.back() / cv.tau.front()) + 1.0, 1.0, static_cast<double>(p));
}

// Line search on a periodogram (see find_spectral_line).
SpectralLine search_line(const PsdResult& psd, double n_seconds, std::span<const double> known,
                         double false_alarm) {
  SpectralLine out;
  out.searched = true;
  out.resolution_hz = psd.df_hz;
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  constexpr std::int64_t kMinBin = 32, kHalf = 64, kCore = 3, kEdge = 8;
  const std::int64_t k_lo = kMinBin, k_hi = kmax - kEdge;
  if (k_hi <= k_lo) {
    out.searched = false;
    return out;
  }
  std::vector<double> window;
  double best_ratio = 0.0, best_bg = 0.0;
  std::int64_t best_k = -1, n_searched = 0;
  for (std::int64_t k = k_lo; k <= k_hi; ++k) {
    const double f = static_cast<double>(k) * psd.df_hz;
    bool near_known = false;
    for (const double fk : known)
      near_known = near_known || std::abs(f - fk) <= 4.0 * psd.df_hz;
    if (near_known) continue;
    ++n_searched;
    // Symmetric window, so that the median of a monotone background is its central value.
    const std::int64_t w = std::min({kHalf, k - 1, kmax - k});
    window.clear();
    for (std::int64_t j = k - w; j <= k + w; ++j)
      if (std::abs(j - k) > kCore) window.push_back(psd.psd[static_cast<std::size_t>(j)]);
    if (window.size() < 8) continue;
    const auto mid = window.begin() + static_cast<std::ptrdiff_t>(window.size() / 2);
    std::nth_element(window.begin(), mid, window.end());
    const double bg = *mid / std::numbers::ln2;
    if (!(bg > 0.0)) continue;
    const double ratio = psd.psd[static_cast<std::size_t>(k)] / bg;
    if (ratio > best_ratio) {
      best_ratio = ratio;
      best_bg = bg;
      best_k = k;
    }
  }
  if (best_k < 0 || n_searched == 0) return out;
  out.threshold = std::log(static_cast<double>(n_searched) / false_alarm);
  out.peak_ratio = best_ratio;
  out.found = best_ratio > out.threshold;
  // Peak frequency by a parabola through the log periodogram at the peak and its neighbours
  // (the Hann main lobe is close to Gaussian in shape, whose log is a parabola).
  const auto at = [&](std::int64_t k) { return std::log(psd.psd[static_cast<std::size_t>(k)]); };
  const double lm = at(best_k - 1), l0 = at(best_k), lp = at(best_k + 1);
  const double den = lm - 2.0 * l0 + lp;
  const double delta = den < 0.0 ? std::clamp(0.5 * (lm - lp) / den, -0.5, 0.5) : 0.0;
  out.frequency_hz = (static_cast<double>(best_k) + delta) * psd.df_hz;
  // The line's power: the periodogram above the background over the main lobe and the first
  // side lobes (the Welch normalization makes sum P df the mean square, so a line of
  // amplitude A contributes A^2 / 2).
  double power = 0.0;
  for (std::int64_t j = best_k - kCore; j <= best_k + kCore; ++j)
    power += (psd.psd[static_cast<std::size_t>(j)] - best_bg) * psd.df_hz;
  out.amplitude = std::sqrt(2.0 * std::max(power, 0.0));
  // Cramer-Rao bound of a tone's frequency in locally white noise of one-sided density S1 over
  // a record of T seconds (Rife & Boorstyn, IEEE Trans. Inf. Theory 20(5), 1974):
  // var(omega) = 24 sigma^2 / (A^2 N^3) per sample, sigma^2 = S1 fs / 2, hence
  // sigma_f = sqrt(3 S1 / (A^2 T^3)) / pi.
  // The amplitude's: var(A) = 2 sigma^2 / N per sample (same reference), i.e. S1 / T.
  out.amplitude_sigma = std::sqrt(best_bg / n_seconds);
  if (out.amplitude > 0.0)
    out.sigma_hz = std::sqrt(3.0 * best_bg /
                             (out.amplitude * out.amplitude * n_seconds * n_seconds * n_seconds)) /
                   std::numbers::pi;
  return out;
}

PsdResult full_periodogram(std::span<const double> rate, double rate_hz, int threads) {
  const auto n = static_cast<std::int64_t>(rate.size());
  const PsdPlan plan(n - n % 2);
  return plan.welch(rate.first(static_cast<std::size_t>(n - n % 2)), rate_hz, threads);
}

bool has_nan(std::span<const double> v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return std::isnan(x); });
}

constexpr std::array<Effect, kNumEffects> kAllEffects = {
    Effect::Quantization, Effect::White,    Effect::Flicker, Effect::RandomWalk,
    Effect::Ramp,         Effect::Sinusoid, Effect::Markov};

struct CandidateFit {
  Candidate info;
  Fit fit;
  std::size_t added = 0;  // index of the added component in fit.comps
};

// tau_c of the Markov component comps[idx] by a log grid of 8 per octave over the curve's
// taus (a hump whose peak, near 1.9 tau_c, lies inside them), then golden-section search on
// ln tau_c between the neighbours of the best grid point; the free coefficients are fitted
// at each tau_c.
Fit search_tau_c(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b) {
  const auto eval = [&](double tau_c) {
    comps[idx].nl = tau_c;
    return fit_components(comps, cv, b);
  };
  const double lo = std::log(cv.tau.front() / 2.0), hi = std::log(cv.tau.back());
  const double step = std::numbers::ln2 / 8.0;
  const int n_grid = static_cast<int>(std::ceil((hi - lo) / step)) + 1;
  double best_chi2 = std::numeric_limits<double>::infinity();
  int best = 0;
  for (int g = 0; g < n_grid; ++g) {
    const Fit f = eval(std::exp(lo + step * g));
    if (f.chi2 < best_chi2) {
      best_chi2 = f.chi2;
      best = g;
    }
  }
  double a = lo + step * std::max(best - 1, 0), c = lo + step * std::min(best + 1, n_grid - 1);
  const double gr = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = c - gr * (c - a), x2 = a + gr * (c - a);
  double f1 = eval(std::exp(x1)).chi2, f2 = eval(std::exp(x2)).chi2;
  for (int it = 0; it < 25; ++it) {
    if (f1 < f2) {
      c = x2;
      x2 = x1;
      f2 = f1;
      x1 = c - gr * (c - a);
      f1 = eval(std::exp(x1)).chi2;
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + gr * (c - a);
      f2 = eval(std::exp(x2)).chi2;
    }
  }
  const double x = f1 < f2 ? x1 : x2;
  Fit grid_best = eval(std::exp(lo + step * best));
  Fit refined = eval(std::exp(x));
  return refined.chi2 <= grid_best.chi2 ? refined : grid_best;
}

// Markov candidate: a new component, its tau_c searched with the others' coefficients as
// `base` has them (fixed or free).
CandidateFit markov_candidate(std::vector<Component> base, const Curve& cv, const Bases& b) {
  Component c;
  c.kind = Kind::Markov;
  c.free = true;
  c.nl_free = true;
  base.push_back(c);
  const std::size_t idx = base.size() - 1;
  CandidateFit out;
  out.fit = search_tau_c(std::move(base), idx, cv, b);
  out.added = out.fit.comps.size() - 1;
  return out;
}

}  // namespace

std::string_view effect_name(Effect e) {
  switch (e) {
  case Effect::Quantization:
    return "quantization";
  case Effect::White:
    return "white";
  case Effect::Flicker:
    return "flicker";
  case Effect::RandomWalk:
    return "random_walk";
  case Effect::Ramp:
    return "ramp";
  case Effect::Sinusoid:
    return "sinusoid";
  case Effect::Markov:
    return "markov";
  }
  return "?";
}

std::optional<Effect> parse_effect(std::string_view name) {
  for (const Effect e : kAllEffects)
    if (effect_name(e) == name) return e;
  return std::nullopt;
}

std::optional<Term> effect_term(Effect e) {
  switch (e) {
  case Effect::Quantization:
    return Term::Q;
  case Effect::White:
    return Term::N;
  case Effect::Flicker:
    return Term::B;
  case Effect::RandomWalk:
    return Term::K;
  case Effect::Ramp:
    return Term::R;
  default:
    return std::nullopt;
  }
}

double diagnose_gap(std::span<const double> avar_measured, std::span<const double> avar_model,
                    std::span<const double> edf) {
  if (avar_measured.size() != avar_model.size() || edf.size() != avar_model.size())
    throw std::invalid_argument("diagnose_gap: unequal lengths");
  if (avar_model.empty()) return 0.0;
  double s = 0.0;
  for (std::size_t i = 0; i < avar_model.size(); ++i) {
    const double z = std::log(avar_measured[i] / avar_model[i]) / std::sqrt(2.0 / edf[i]);
    s += z * z;
  }
  return std::sqrt(s / static_cast<double>(avar_model.size()));
}

SpectralLine find_spectral_line(std::span<const double> rate, double rate_hz,
                                std::span<const double> known_hz, double false_alarm,
                                int nthreads) {
  if (!(false_alarm > 0.0 && false_alarm < 1.0))
    throw std::invalid_argument("find_spectral_line: false_alarm must be in (0, 1), got " +
                                std::to_string(false_alarm));
  if (rate.size() < 256 || has_nan(rate)) return {};
  const PsdResult psd = full_periodogram(rate, rate_hz, resolve_threads(nthreads));
  return search_line(psd, static_cast<double>(rate.size() - rate.size() % 2) / rate_hz, known_hz,
                     false_alarm);
}

Diagnosis diagnose(std::span<const double> rate, double rate_hz, const ChannelSpec& model,
                   const DiagnoseOptions& opt) {
  if (opt.taus_per_decade < 1 || opt.taus_per_decade > 100)
    throw std::invalid_argument("diagnose: taus_per_decade must be in [1, 100], got " +
                                std::to_string(opt.taus_per_decade));
  if (!(opt.band_alpha > 0.0 && opt.band_alpha < 1.0))
    throw std::invalid_argument("diagnose: band_alpha must be in (0, 1)");
  if (!(opt.select_alpha > 0.0 && opt.select_alpha < 1.0))
    throw std::invalid_argument("diagnose: select_alpha must be in (0, 1)");
  if (opt.mc_replicas < 0) throw std::invalid_argument("diagnose: mc_replicas must be >= 0");
  const int threads = resolve_threads(opt.nthreads);
  ChannelSpec spec = model;
  spec.rate_hz = rate_hz;
  validate(spec);

  Diagnosis d;
  // The measurement: overlapping Allan variance on a log grid with its Greenhall-Riley edf.
  const PhaseData phase = phase_from_rate(rate, rate_hz, threads);
  const std::int64_t m_max = max_m(Stat::Oadev, phase.n_points());
  if (m_max < 8)
    throw std::invalid_argument("diagnose: record too short (" + std::to_string(rate.size()) +
                                " samples); need at least 3 octaves of tau (33 samples)");
  TauGridSpec grid;
  grid.kind = TauGridKind::Log;
  grid.per_decade = opt.taus_per_decade;
  StatResult oadev = compute(Stat::Oadev, phase, make_m_list(grid, m_max), threads);
  add_confidence(Stat::Oadev, phase, oadev, kDefaultConfidence, threads);
  Curve cv;
  cv.tau0 = 1.0 / rate_hz;
  cv.n_samples = static_cast<std::int64_t>(rate.size());
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    const double y = oadev.dev[i] * oadev.dev[i];
    if (!(y > 0.0) || !(oadev.edf[i] > 0.0)) continue;  // ln 0: nothing to compare
    cv.m.push_back(oadev.m[i]);
    cv.n.push_back(oadev.n[i]);
    cv.tau.push_back(oadev.tau_s[i]);
    cv.y.push_back(y);
    cv.edf.push_back(oadev.edf[i]);
    const double half = 0.5 * oadev.edf[i];
    cv.ln_y.push_back(std::log(y) - (digamma(half) - std::log(half)));
    cv.var_ln.push_back(trigamma(half));
  }
  if (cv.size() < 4)
    throw std::invalid_argument("diagnose: fewer than 4 taus with a non-zero Allan variance");
  d.m = cv.m;
  d.n = cv.n;
  d.tau_s = cv.tau;
  d.avar_measured = cv.y;
  d.edf = cv.edf;
  d.n_eff = effective_taus(cv);
  // Selection threshold for a candidate of k parameters: the chi-square quantile at
  // select_alpha / kNumEffects (Bonferroni over the candidates of a round), so that a round adds
  // an effect to a complete model with probability about select_alpha.
  const auto threshold = [&](int k, double alpha) {
    return chi2_quantile(1.0 - alpha, static_cast<double>(k));
  };
  const double alpha_cand = opt.select_alpha / kNumEffects;
  d.penalty = threshold(1, alpha_cand);
  const double alpha_tau = opt.band_alpha / d.n_eff;
  d.z_threshold = std::sqrt(chi2_quantile(1.0 - alpha_tau, 1.0));
  const double scale = d.n_eff / static_cast<double>(cv.size());
  const Bases bases = make_bases(cv, rate_hz);

  d.model_before = spec;
  d.before = compare(cv, model_curve(spec, cv, bases), alpha_tau);

  std::optional<PsdResult> periodogram;
  if (has_nan(rate))
    d.notes.push_back("the record has gaps: no PSD witness, so no sinusoid can be named");
  else if (rate.size() >= 256)
    periodogram = full_periodogram(rate, rate_hz, threads);
  const double t_record = static_cast<double>(rate.size() - rate.size() % 2) / rate_hz;

  // The add-and-repeat loop. Each round compares, against the current model with its
  // coefficients as they stand, (a) each candidate added with the current coefficients fixed,
  // (b) each candidate added with them re-estimated, and (c) the coefficients re-estimated with
  // nothing added; the threshold grows with the parameters each hypothesis frees. Re-estimating
  // is allowed but must pay for itself: a higher flicker floor can always absorb part of a
  // missing hump or rise, and without (a) the free refit would swallow effects it cannot
  // actually explain.
  std::vector<Component> given = components_of(spec);
  std::vector<Component> current = given;
  std::vector<std::size_t> added_idx;
  bool refit_taken = false;
  const auto evaluate = [&](Effect e, std::vector<Component> comps, const SpectralLine& line,
                            int n_refit, double chi2_ref) {
    CandidateFit cf;
    cf.info.effect = e;
    int k = n_refit;
    if (const auto t = effect_term(e)) {
      const bool present = std::any_of(comps.begin(), comps.end(), [&](const auto& c) {
        return c.kind == Kind::Term && c.term == *t;
      });
      if (present) {
        cf.info.note = "already in the model";
        return cf;
      }
      Component c;
      c.term = *t;
      c.free = true;
      comps.push_back(c);
      cf.fit = fit_components(std::move(comps), cv, bases);
      k += 1;
    } else if (e == Effect::Sinusoid) {
      if (!line.searched) {
        cf.info.note = "no PSD witness (gaps or short record)";
        return cf;
      }
      if (!line.found || line.frequency_hz > 0.5 * rate_hz) {
        cf.info.note = "the PSD shows no line (peak/background " + std::to_string(line.peak_ratio) +
                       " < threshold " + std::to_string(line.threshold) + ")";
        return cf;
      }
      Component c;
      c.kind = Kind::Sinusoid;
      c.nl = line.frequency_hz;
      c.nl_sigma = line.sigma_hz;
      c.coef = line.amplitude;
      c.coef_sigma = line.amplitude_sigma;
      c.pinned = true;
      comps.push_back(c);
      cf.fit = fit_components(std::move(comps), cv, bases);
      cf.info.note = "PSD line at " + std::to_string(line.frequency_hz) + " Hz, peak/background " +
                     std::to_string(line.peak_ratio);
      k += 2;
    } else if (e == Effect::Markov) {
      const auto n_markov = std::count_if(comps.begin(), comps.end(),
                                          [](const auto& c) { return c.kind == Kind::Markov; });
      if (static_cast<std::uint32_t>(n_markov) >= rng::kMaxMarkov) {
        cf.info.note = "too many markov effects";
        return cf;
      }
      cf = markov_candidate(comps, cv, bases);
      cf.info.effect = e;
      k += 2;
    }
    cf.added = cf.fit.comps.size() - 1;
    cf.info.evaluated = true;
    cf.info.delta_ic = (chi2_ref - cf.fit.chi2) * scale - threshold(k, alpha_cand);
    std::vector<double> cs, ns;
    fill_sigmas(cf.fit, cv, bases, d.n_eff, cs, ns);
    cf.info.parameters = parameters_of(cf.fit.comps[cf.added], cs[cf.added], ns[cf.added]);
    return cf;
  };

  for (int iter = 0; iter < opt.max_effects;) {
    std::vector<Component> fixed_now = current, free_now = current;
    for (Component& c : fixed_now)
      c.free = false;
    for (Component& c : free_now)
      c.free = !c.pinned;
    const Fit ref = fit_components(fixed_now, cv, bases);
    const int n_free = static_cast<int>(
        std::count_if(free_now.begin(), free_now.end(), [](const auto& c) { return c.free; }));
    std::vector<double> known_f;
    for (const Component& c : current)
      if (c.kind == Kind::Sinusoid) known_f.push_back(c.nl);
    SpectralLine line;
    if (periodogram) line = search_line(*periodogram, t_record, known_f, opt.line_false_alarm);
    if (iter == 0 && !refit_taken) d.line = line;
    // Variant (b) is judged against the refit, not against the model as it stands: its effect
    // must pay for itself beyond what re-estimating alone achieves, or any useless term would
    // ride on the refit's improvement.
    const Fit refit = fit_components(free_now, cv, bases);
    std::vector<CandidateFit> cands;
    for (const Effect e : kAllEffects) {
      CandidateFit a = evaluate(e, fixed_now, line, 0, ref.chi2);
      if (n_free > 0) {
        CandidateFit b = evaluate(e, free_now, line, 0, refit.chi2);
        b.info.note +=
            (b.info.note.empty() ? "" : "; ") + std::string("with the coefficients re-estimated");
        if (b.info.evaluated && (!a.info.evaluated || b.info.delta_ic > a.info.delta_ic))
          a = std::move(b);
      }
      cands.push_back(std::move(a));
    }
    std::size_t best = cands.size();
    for (std::size_t c = 0; c < cands.size(); ++c)
      if (cands[c].info.evaluated && cands[c].info.delta_ic > 0.0 &&
          (best == cands.size() || cands[c].info.delta_ic > cands[best].info.delta_ic))
        best = c;
    // The PSD witness decides between look-alikes: an unexplained significant line is direct
    // evidence of a sinusoid, while a Gauss-Markov hump (no line) can mimic its Allan bump. So
    // when the sinusoid candidate is significant it goes first; the others are judged again in
    // the next round, with the line explained.
    for (std::size_t c = 0; c < cands.size(); ++c)
      if (cands[c].info.effect == Effect::Sinusoid && cands[c].info.evaluated &&
          cands[c].info.delta_ic > 0.0)
        best = c;
    // (c): the coefficients re-estimated with nothing added, taken at most once and only when
    // no effect is significant: incomplete before wrong, because a raised flicker floor can
    // mimic two hidden effects at once (a greedy round cannot see that one effect now and one
    // next round explain more); whether the given values were wrong is tested again at the end
    // with every effect in place.
    if (n_free > 0 && !refit_taken) {
      const double delta = (ref.chi2 - refit.chi2) * scale - threshold(n_free, alpha_cand);
      if (delta > 0.0 && best == cands.size()) {
        refit_taken = true;
        current = refit.comps;
        d.notes.push_back("round " + std::to_string(iter + 1) +
                          ": re-estimating the model's coefficients explains more than adding "
                          "any effect (criterion +" +
                          std::to_string(delta) + ")");
        continue;
      }
    }
    if (best == cands.size()) break;
    CandidateFit& w = cands[best];
    Iteration it;
    it.effect = w.info.effect;
    it.parameters = w.info.parameters;
    it.delta_ic = w.info.delta_ic;
    const Comparison cmp_before = compare(cv, ref.model, alpha_tau);
    const Comparison cmp_after = compare(cv, w.fit.model, alpha_tau);
    it.gap_before = iter == 0 ? d.before.gap : cmp_before.gap;
    it.gap_after = cmp_after.gap;
    it.bands_before = iter == 0 ? d.before.bands : cmp_before.bands;
    it.bands_after = cmp_after.bands;
    std::vector<double> cs, ns;
    fill_sigmas(w.fit, cv, bases, d.n_eff, cs, ns);
    for (std::size_t c = 0; c < w.fit.comps.size(); ++c) {
      const std::string label = component_label(w.fit.comps, c);
      for (Parameter p : parameters_of(w.fit.comps[c], cs[c], ns[c])) {
        if (w.fit.comps[c].kind != Kind::Term) p.name = label + "." + p.name;
        it.coefficients.push_back(p);
      }
    }
    it.model_after = spec_of(w.fit.comps, spec);
    for (CandidateFit& c : cands)
      it.candidates.push_back(c.info);
    d.iterations.push_back(std::move(it));
    d.effects_named.push_back(w.info.effect);
    added_idx.push_back(w.added);
    current = w.fit.comps;
    ++iter;
  }
  std::vector<Component> all_free = current;
  for (Component& c : all_free)
    c.free = !c.pinned;
  Fit base = fit_components(all_free, cv, bases);
  // Each added Markov effect's tau_c was searched in the round that named it, before the
  // effects named after it were in the model (a quantization found later, say, had been
  // partly absorbed by the hump); it is searched again with the final structure.
  for (const std::size_t idx : added_idx)
    if (base.comps[idx].kind == Kind::Markov) base = search_tau_c(base.comps, idx, cv, bases);

  // Were the given coefficients wrong? The final structure with the given components fixed at
  // their given values (the added effects still fitted) against all re-estimated; the same
  // criterion, with one parameter per given coefficient.
  std::vector<Component> fixed = base.comps;
  int n_given = 0;
  for (std::size_t c = 0; c < fixed.size(); ++c)
    if (c < given.size()) {
      fixed[c] = given[c];
      fixed[c].free = false;
      ++n_given;
    }
  Fit fixed_fit = fit_components(fixed, cv, bases);
  d.revision_delta_ic =
      n_given > 0 ? (fixed_fit.chi2 - base.chi2) * scale - threshold(n_given, opt.select_alpha)
                  : 0.0;
  d.coefficients_wrong = n_given > 0 && d.revision_delta_ic > 0.0;
  std::vector<double> cs, ns;
  fill_sigmas(base, cv, bases, d.n_eff, cs, ns);
  for (std::size_t c = 0; c < given.size(); ++c) {
    const std::string label = component_label(given, c);
    const std::string key = given[c].kind == Kind::Term       ? label
                            : given[c].kind == Kind::Sinusoid ? label + ".amplitude"
                                                              : label + ".sigma";
    d.revisions.push_back({key, given[c].coef, base.comps[c].coef, cs[c]});
  }
  Fit& final_fit = d.coefficients_wrong ? base : fixed_fit;
  if (d.effects_named.empty() && !d.coefficients_wrong) {
    d.model_after = spec;
  } else {
    d.model_after = spec_of(final_fit.comps, spec);
  }
  std::vector<double> fcs, fns;
  fill_sigmas(final_fit, cv, bases, d.n_eff, fcs, fns);
  for (const std::size_t idx : added_idx)
    d.effect_parameters.push_back(parameters_of(final_fit.comps[idx], fcs[idx], fns[idx]));
  d.after = compare(cv, model_curve(d.model_after, cv, bases), alpha_tau);

  d.mc_before =
      monte_carlo(d.model_before, cv, d.before.avar_model, opt.mc_replicas, opt.mc_seed, threads);
  const bool same = d.model_after.terms == d.model_before.terms &&
                    d.model_after.sinusoids == d.model_before.sinusoids &&
                    d.model_after.markovs == d.model_before.markovs;
  d.mc_after = same ? d.mc_before
                    : monte_carlo(d.model_after, cv, d.after.avar_model, opt.mc_replicas,
                                  opt.mc_seed, threads);
  d.gap_within_noise = opt.mc_replicas > 0 ? d.after.gap <= d.mc_after.gap_p95 : d.after.gap <= 1.0;
  return d;
}

}  // namespace allanlot::kernels
