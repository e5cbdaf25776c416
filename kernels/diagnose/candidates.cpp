// Diagnose's model components (docs/diagnose.md "Why"): their basis curves, their fits to the
// measured curve, the uncertainties of their parameters and the candidates of a round.
#include "kernels/diagnose/internal.hpp"

#include "kernels/common/tasks.hpp"

#include "kernels/model/least_squares.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace allanlot::kernels::diagnose_detail {
namespace {

// A line's unit curve under b's filter. model_avar, not model_avar_sampled: both are exact for a
// line at every m, and the sampled form would evaluate flicker's quadrature factor for nothing.
std::vector<double> line_basis(double frequency_hz, const Curve& cv, const Bases& b) {
  ChannelSpec s;
  s.rate_hz = b.rate_hz;
  s.sinusoids.push_back({1.0, frequency_hz, 0.0});
  std::vector<double> g(cv.size());
  const double gain = lowpass_gain2(b.lowpass, b.rate_hz, frequency_hz);
  for (std::size_t i = 0; i < cv.size(); ++i)
    g[i] = gain * model_avar(s, cv.tau[i]);
  return g;
}

// The Allan variance of c at unit level at the curve's taus under b's filter; none (zeros) for a
// filter, which reshapes the others', and a step, which is removed from the record instead
// (diagnose.cpp, Search::curve_without): no variance on the curves compared.
std::vector<double> basis_of(const Component& c, const Curve& cv, const Bases& b) {
  return std::visit(
      [&](const auto& p) -> std::vector<double> {
        using E = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<E, TermLevel>)
          return b.term[static_cast<std::size_t>(p.term)];
        else if constexpr (std::is_same_v<E, Sinusoid>)
          return line_basis(p.frequency_hz, cv, b);
        else if constexpr (std::is_same_v<E, GaussMarkov> || std::is_same_v<E, Resonance>)
          return shaped_curve(c, cv, b);
        else if constexpr (std::is_same_v<E, Lowpass> || std::is_same_v<E, Step>)
          return std::vector<double>(cv.size(), 0.0);
        else
          static_assert(kUnhandled<E>, "a part without its Allan variance on the curve");
      },
      c.part);
}

// The bases of a set of components: `b` itself when it already carries the set's filter (the
// lowpass candidate filters once per trial filter), else the unfiltered `b` filtered.
Bases bases_for(const std::vector<Component>& comps, const Curve& cv, const Bases& b) {
  const Lowpass lp = lowpass_of(comps);
  if (lp == b.lowpass) return b;
  if (b.lowpass.active()) throw std::logic_error("diagnose: bases of another filter");
  return filtered_bases(b, cv, lp);
}

}  // namespace

// The filter of the lowpass component comps[idx]: first-order filters with cutoffs on a log grid of
// 8 per octave from rate / 200 to 0.45 rate (above, the filter changes no tau of the grid
// measurably) and moving averages over 1.05 to 16 samples on the same kind of grid (a non-integer
// length is the boxcar of a sensor that averages a faster internal rate before decimating: the
// ADIS16405's deficit is steeper than a one-pole filter's), each fitted with the other components
// as `base` has them; each form's best is refined between its neighbours and the better of the
// two kept (below). A value at either end of its grid is a limit.
Fit search_lowpass(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b) {
  const double lo = std::log(b.rate_hz / 200.0), hi = std::log(0.45 * b.rate_hz);
  const int n_grid = static_cast<int>(std::ceil((hi - lo) / (std::numbers::ln2 / 8.0))) + 1;
  const double t_lo = std::log(1.05), t_hi = std::log(16.0);
  const int n_taps = static_cast<int>(std::ceil((t_hi - t_lo) / (std::numbers::ln2 / 8.0))) + 1;
  // Grid point x (0 .. n_grid - 1: cutoffs; n_grid .. n_grid + n_taps - 1: taps; a fraction
  // between points of one form interpolates on the log scale).
  const auto fit_with = [&](std::vector<Component>& own, double x) {
    Lowpass lp;
    if (x < n_grid)
      lp.cutoff_hz = std::exp(lo + (hi - lo) * x / (n_grid - 1));
    else
      lp.taps = std::exp(t_lo + (t_hi - t_lo) * (x - n_grid) / (n_taps - 1));
    as<Lowpass>(own[idx]) = lp;
    return fit_components(own, cv, filtered_bases(b, cv, lp));
  };
  const auto fit_at = [&](double x) { return fit_with(comps, x); };
  // The grid's fits are independent (each on its own copy of the components): made as tasks
  // (for_each_index) and read in the grid's order below, so the same point wins whatever thread
  // made each fit. Each is a new filter, so every hump's and resonance's curve under it is
  // computed afresh: the grid is most of a refit's time.
  std::vector<Fit> grid(static_cast<std::size_t>(n_grid + n_taps));
  for_each_index(n_grid + n_taps, 1, [&](std::int64_t g) {
    std::vector<Component> own = comps;
    grid[static_cast<std::size_t>(g)] = fit_with(own, static_cast<double>(g));
  });
  // Each form's best grid point is refined by a golden-section search between its neighbours:
  // the grid's step (9 %) is coarse against what a long record resolves (the ADIS16405's
  // deficit at tau0 has an edf of 10^5), so the forms are compared refined. Compared on the
  // grid, a one-pole point that happened to lie nearer its optimum than the boxcar's beat the
  // 2-tap boxcar the ADIS16405 x gyroscopes have, and a broad resonance was named for the shape
  // the one-pole lacked.
  Fit out;
  double best = std::numeric_limits<double>::infinity();
  int best_g = -1;
  for (const auto& [first, last] :
       {std::pair{0, n_grid - 1}, std::pair{n_grid, n_grid + n_taps - 1}}) {
    Fit form_best;
    int g_best = first;
    for (int g = first; g <= last; ++g)
      if (Fit& f = grid[static_cast<std::size_t>(g)]; g == first || f.chi2 < form_best.chi2) {
        form_best = std::move(f);
        g_best = g;
      }
    const double x = golden_min([&](double v) { return fit_at(v).chi2; },
                                std::max(g_best - 1, first), std::min(g_best + 1, last));
    if (Fit f = fit_at(x); f.chi2 < form_best.chi2) form_best = std::move(f);
    if (form_best.chi2 < best) {
      best = form_best.chi2;
      best_g = g_best;
      out = std::move(form_best);
    }
  }
  // At the bottom of either grid the value is an upper limit, at the top a lower one.
  const int last = n_grid + n_taps - 1;
  out.comps[idx].nl_bound = best_g == 0 || best_g == n_grid          ? -1
                            : best_g == n_grid - 1 || best_g == last ? 1
                                                                     : 0;
  return out;
}

// Lowpass candidate: a new component, its filter searched with the others as `base` has them.
CandidateFit lowpass_candidate(std::vector<Component> base, const Curve& cv, const Bases& b) {
  Component c = component(Lowpass{});
  c.pinned = true;
  base.push_back(c);
  CandidateFit out;
  out.added = base.size() - 1;
  out.fit = search_lowpass(std::move(base), out.added, cv, b);
  // A resonance named before the filter had its frequency and q fitted to the unfiltered
  // curve, where they took up part of the filter's deficit (the ADIS16405 z gyroscopes: a
  // Gauss-Markov hump at one sample then stood in for the filter, 1597 against 804). Under the
  // chosen filter they are searched again near where they are, when the coefficients are
  // re-estimated (with them fixed, the model as it stands keeps its resonance).
  const Bases chosen = filtered_bases(b, cv, as<Lowpass>(out.fit.comps[out.added]));
  for (std::size_t i = 0; i < out.added; ++i)
    if (is<Resonance>(out.fit.comps[i]) && out.fit.comps[i].nl_free && out.fit.comps[i].free) {
      Fit f = search_resonance(out.fit.comps, i, cv, chosen, false);
      if (f.chi2 < out.fit.chi2) out.fit = std::move(f);
    }
  return out;
}

namespace {

// Diagnose's choices for the one NNLS (kernels/model/least_squares.hpp): a tolerance of
// 1e-12 |A| max(1, |b|), at most 3 k + 3 additions and k + 1 steps each for k columns, a
// coefficient at or below 1e-300 leaves the active set. These are the choices the component
// fit has always made, kept so that its results stay bit for bit: the fits' kEq3Nnls gives the
// same bits on the test scenarios, but not by construction wherever a tolerance or limit binds.
constexpr detail::NnlsOptions kComponentNnls{1e-12, 1.0, 3, 3, 1, 1, 1e-300, false, false};

double log_chi2(const Curve& cv, const std::vector<double>& model) {
  double s = 0.0;
  for (std::size_t i = 0; i < cv.size(); ++i) {
    const double r = cv.ln_y[i] - std::log(std::max(model[i], 1e-300));
    s += r * r / cv.var_ln[i];
  }
  return s;
}

std::string term_key(Term t) {
  return std::string(term_name(t));
}

// A resonance's parameters: its shape measured on the periodogram (pinned or psd_shape: the
// sigmas of that fit; a wandering one's spread with it, and the wander's correlation time from
// its track, an order of magnitude with no sigma) or searched on the curve (q's sigma NaN at a
// bound of its range).
std::vector<Parameter> resonance_parameters_of(const Component& c, double coef_sigma,
                                               double nl_sigma, double q_sigma) {
  const Resonance& r = as<Resonance>(c);
  if (!c.pinned && !c.psd_shape)
    return {{"sigma", r.sigma, coef_sigma},
            {"frequency_hz", r.frequency_hz, nl_sigma, c.nl_bound},
            {"q", r.q, c.q_bound != 0 ? kNaN : q_sigma, c.q_bound}};
  std::vector<Parameter> out = {{"sigma", r.sigma, coef_sigma},
                                {"frequency_hz", r.frequency_hz, c.nl_sigma},
                                {"q", r.q, c.q_sigma}};
  if (r.spread_hz > 0.0) {
    out.push_back({"spread_hz", r.spread_hz, c.spread_sigma});
    out.push_back({"wander_s", r.wander_s, kNaN});
  }
  return out;
}

}  // namespace

// A jump as a component, pinned (never refitted on the curve).
Component step_component(const Step& st) {
  Component c = component(st);
  c.pinned = true;
  return c;
}

Component searched_component(Part p) {
  Component c = component(p);
  c.free = true;
  c.nl_free = true;
  return c;
}

double threshold(int k, double alpha) {
  if (k == 0) return 0.0;
  return chi2_quantile(1.0 - alpha, static_cast<double>(k));
}

Lowpass lowpass_of(const std::vector<Component>& comps) {
  for (const Component& c : comps)
    if (is<Lowpass>(c)) return as<Lowpass>(c);
  return {};
}

Bases filtered_bases(const Bases& raw, const Curve& cv, const Lowpass& lp) {
  Bases b = raw;
  b.lowpass = lp;
  auto& n = b.term[static_cast<std::size_t>(Term::N)];
  auto& q = b.term[static_cast<std::size_t>(Term::Q)];
  for (std::size_t i = 0; i < cv.size(); ++i) {
    n[i] *= lowpass_white_fm_factor(lp, raw.rate_hz, cv.m[i]);
    q[i] *= lowpass_white_pm_factor(lp, raw.rate_hz, cv.m[i]);
  }
  return b;
}

Bases make_bases(const Curve& cv, double rate_hz, double quantum) {
  Bases b;
  b.rate_hz = rate_hz;
  b.fixed.resize(cv.size());
  for (std::size_t i = 0; i < cv.size(); ++i)
    b.fixed[i] = quantum * quantum / (12.0 * static_cast<double>(cv.m[i]));
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
    if (coefficient(s.terms, t) > 0.0)
      out.push_back(component(TermLevel{t, coefficient(s.terms, t)}));
  // The effects in kEffectLists' order. A given jump is pinned: the Allan curve can neither
  // place it nor size it apart from a random walk.
  for_each_effect_list(s, [&](const auto& list) {
    for (const auto& e : list) {
      out.push_back(component(e));
      out.back().pinned = is<Step>(out.back());
    }
  });
  if (s.lowpass.active()) {
    out.push_back(component(s.lowpass));
    out.back().pinned = true;
  }
  for (Component& c : out)
    c.given = true;
  return out;
}

ChannelSpec spec_of(const std::vector<Component>& comps, const ChannelSpec& like) {
  ChannelSpec s;
  s.rate_hz = like.rate_hz;
  s.offset = like.offset;
  s.quantum = like.quantum;
  for (const Component& c : comps)
    std::visit(
        [&s](const auto& p) {
          using E = std::decay_t<decltype(p)>;
          if constexpr (std::is_same_v<E, TermLevel>)
            coefficient(s.terms, p.term) = p.coef;
          else if constexpr (std::is_same_v<E, Lowpass>)
            s.lowpass = p;
          else
            for_each_effect_list(s, [&p](auto& list) {
              if constexpr (std::is_same_v<typename std::decay_t<decltype(list)>::value_type, E>)
                list.push_back(p);
            });
        },
        c.part);
  return s;
}

// Fits the squared coefficients of the free components (the others fixed), as kernels/model/fit.hpp
// does for eq. (3): non-negative weighted least squares on the variances with weights
// 1 / var(avar_hat) = 1 / (var_ln avar_model^2), reweighted from the model until it settles.
// Weights from the model rather than the estimate avoid favouring estimates that fell low. To
// first order this minimizes the chi-square of the log residuals that the criterion uses.
Fit fit_components(std::vector<Component> comps, const Curve& cv, const Bases& raw) {
  const Bases b = bases_for(comps, cv, raw);
  const std::size_t p = cv.size();
  std::vector<std::vector<double>> g;
  std::vector<std::size_t> free_idx;
  std::vector<double> fixed = b.fixed;
  fixed.resize(p, 0.0);
  for (std::size_t c = 0; c < comps.size(); ++c) {
    std::vector<double> gc = basis_of(comps[c], cv, b);
    if (comps[c].free) {
      free_idx.push_back(c);
      g.push_back(std::move(gc));
    } else {
      const double level = coef(comps[c]);
      for (std::size_t i = 0; i < p; ++i)
        fixed[i] += level * level * gc[i];
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
      set_coef(comps[free_idx[static_cast<std::size_t>(j)]], std::sqrt(std::max(theta(j), 0.0)));
  }
  Fit f;
  f.comps = std::move(comps);
  f.model = std::move(model);
  f.chi2 = log_chi2(cv, f.model);
  return f;
}

Eigen::MatrixXd free_columns(const std::vector<Component>& comps, std::span<const double> model,
                             const Curve& cv, const Bases& raw) {
  const Bases b = bases_for(comps, cv, raw);
  const auto p = static_cast<Eigen::Index>(cv.size());
  std::vector<Eigen::VectorXd> cols;
  for (const Component& c : comps) {
    if (!c.free || is<Lowpass>(c) || is<Step>(c)) continue;
    const std::vector<double> g = basis_of(c, cv, b);
    Eigen::VectorXd col(p);
    for (Eigen::Index i = 0; i < p; ++i) {
      const auto u = static_cast<std::size_t>(i);
      col(i) = g[u] / (std::sqrt(cv.var_ln[u]) * std::max(model[u], 1e-300));
    }
    cols.push_back(std::move(col));
  }
  Eigen::MatrixXd a(p, static_cast<Eigen::Index>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j)
    a.col(static_cast<Eigen::Index>(j)) = cols[j];
  return a;
}

// Uncertainties of the free parameters of a fit, from the log-space Fisher information
// F = J^T diag(1 / var_ln) J with J_ij = d ln avar_model_i / d p_j (p: the coefficients
// themselves, and tau_c, a resonance's frequency and q where they were searched), inflated by
// P / n_eff because the P estimates carry only about n_eff independent pieces of information
// (see the header). Parameters held at zero get NaN (their uncertainty is not a Gaussian one).
Sigmas fill_sigmas(const Fit& f, const Curve& cv, const Bases& raw, double n_eff) {
  const Bases b = bases_for(f.comps, cv, raw);
  const std::size_t p = cv.size();
  Sigmas out;
  out.coef.assign(f.comps.size(), kNaN);
  out.nl.assign(f.comps.size(), kNaN);
  out.q.assign(f.comps.size(), kNaN);
  std::vector<std::pair<std::size_t, std::vector<double>*>> params;  // (component, where)
  std::vector<std::vector<double>> cols;
  // d ln avar / d x of a shape parameter x of effect E (a field of its part), by central
  // differences of relative step 1e-4.
  const auto nonlinear = [&]<class E>(std::size_t c, double E::*x, std::vector<double>* where) {
    const Component& comp = f.comps[c];
    const double h = 1e-4, level = coef(comp), at = as<E>(comp).*x;
    Component lo = comp, hi = comp;
    as<E>(lo).*x *= 1.0 - h;
    as<E>(hi).*x *= 1.0 + h;
    const std::vector<double> gl = basis_of(lo, cv, b), gh = basis_of(hi, cv, b);
    std::vector<double> dn(p);
    for (std::size_t i = 0; i < p; ++i)
      dn[i] = level * level * (gh[i] - gl[i]) / (2.0 * h * at) / f.model[i];
    params.emplace_back(c, where);
    cols.push_back(std::move(dn));
  };
  for (std::size_t c = 0; c < f.comps.size(); ++c) {
    const Component& comp = f.comps[c];
    const double level = coef(comp);
    if (!comp.free || !(level > 0.0)) continue;
    const std::vector<double> g = basis_of(comp, cv, b);
    std::vector<double> d(p);
    for (std::size_t i = 0; i < p; ++i)
      d[i] = 2.0 * level * g[i] / f.model[i];
    params.emplace_back(c, &out.coef);
    cols.push_back(std::move(d));
    if (!comp.nl_free) continue;
    // Only humps and resonances have their shapes searched on the curve.
    if (is<GaussMarkov>(comp)) nonlinear(c, &GaussMarkov::tau_c_s, &out.nl);
    if (is<Resonance>(comp)) {
      nonlinear(c, &Resonance::frequency_hz, &out.nl);
      nonlinear(c, &Resonance::q, &out.q);
    }
  }
  if (params.empty()) return out;
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
    const auto [c, where] = params[static_cast<std::size_t>(q)];
    (*where)[c] = std::sqrt(std::max(cov(q, q), 0.0));
  }
  return out;
}

// The parameters of one component under the model file's keys.
std::vector<Parameter> parameters_of(const Component& c, const Sigmas& sigmas, std::size_t idx) {
  const double coef_sigma = c.pinned ? c.coef_sigma : sigmas.coef[idx];
  // A shape at the end of its search range is a limit, not an estimate: its curvature-based
  // sigma would describe the edge of the grid, not the data.
  const double nl_sigma = c.nl_bound != 0 ? kNaN : sigmas.nl[idx];
  return std::visit(
      [&](const auto& p) -> std::vector<Parameter> {
        using E = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<E, TermLevel>) {
          return {{term_key(p.term), p.coef, coef_sigma}};
        } else if constexpr (std::is_same_v<E, Lowpass>) {
          return {p.taps > 0 ? Parameter{"taps", p.taps, kNaN, c.nl_bound}
                             : Parameter{"cutoff_hz", p.cutoff_hz, kNaN, c.nl_bound}};
        } else if constexpr (std::is_same_v<E, Sinusoid>) {
          return {{"amplitude", p.amplitude, coef_sigma},
                  {"frequency_hz", p.frequency_hz,
                   std::isnan(c.nl_sigma) ? sigmas.nl[idx] : c.nl_sigma}};
        } else if constexpr (std::is_same_v<E, Step>) {
          return {{"size", p.size, c.coef_sigma}, {"time_s", p.time_s, c.nl_sigma}};
        } else if constexpr (std::is_same_v<E, Resonance>) {
          return resonance_parameters_of(c, coef_sigma, nl_sigma, sigmas.q[idx]);
        } else if constexpr (std::is_same_v<E, GaussMarkov>) {
          return {{"sigma", p.sigma, coef_sigma}, {"tau_c_s", p.tau_c_s, nl_sigma, c.nl_bound}};
        } else {
          static_assert(kUnhandled<E>, "a part without its parameters");
        }
      },
      c.part);
}

std::string component_label(const std::vector<Component>& comps, std::size_t idx) {
  const Component& c = comps[idx];
  if (is<TermLevel>(c)) return term_key(as<TermLevel>(c).term);
  if (is<Lowpass>(c)) return std::string(EffectTraits<Lowpass>::name);
  int ordinal = 0;
  for (std::size_t i = 0; i < idx; ++i)
    ordinal += comps[i].part.index() == c.part.index() ? 1 : 0;
  return std::string(effect_name(effect_of(c))) + "[" + std::to_string(ordinal) + "]";
}

// model_avar_sampled of spec `s` at the curve's taus, from the cached term bases.
std::vector<double> model_curve(const ChannelSpec& s, const Curve& cv, const Bases& raw) {
  const Bases b = s.lowpass.active() ? filtered_bases(raw, cv, s.lowpass) : raw;
  std::vector<double> v(cv.size());
  ChannelSpec effects = s;
  effects.terms = {};
  effects.markovs.clear();
  effects.resonances.clear();
  for (Sinusoid& q : effects.sinusoids)
    q.amplitude *= std::sqrt(lowpass_gain2(s.lowpass, s.rate_hz, q.frequency_hz));
  std::vector<std::vector<double>> markovs;
  for (const GaussMarkov& g : s.markovs)
    markovs.push_back(markov_curve(g.sigma, g.tau_c_s, cv, s.lowpass, s.rate_hz));
  for (const Resonance& r : s.resonances)
    markovs.push_back(resonance_curve(r, cv, s.lowpass, s.rate_hz));
  for (std::size_t i = 0; i < cv.size(); ++i) {
    v[i] = model_avar(effects, cv.tau[i]);
    for (const std::vector<double>& g : markovs)
      v[i] += g[i];
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

double golden_min(const std::function<double(double)>& f, double a, double c) {
  const double gr = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = c - gr * (c - a), x2 = a + gr * (c - a);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 25; ++it) {
    if (f1 < f2) {
      c = x2;
      x2 = x1;
      f2 = f1;
      x1 = c - gr * (c - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + gr * (c - a);
      f2 = f(x2);
    }
  }
  return f1 < f2 ? x1 : x2;
}

}  // namespace allanlot::kernels::diagnose_detail
