// The drift models' fits (drift.hpp). Each model is a linear least-squares problem in its
// columns g_c(t); log and diffusion have one nonlinear parameter (b, c), searched on a log grid
// and refined by golden section, the others solved for at each trial value.
#include "kernels/drift/drift.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

using LMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using LVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
// The model's columns at time t: g[0..k-1].
using Columns = std::function<void(double t, double* g)>;

constexpr int kMaxColumns = 3;

// Least squares in the columns over the valid samples: the coefficients, the residual sum of
// squares and (A^T A)^-1. Normal equations in long double with the columns scaled to unit
// diagonal, which keeps them well conditioned for the few smooth columns used here.
struct LinearSolve {
  std::vector<double> beta;
  LMatrix inverse;
  long double sse = 0;
  bool ok = false;
};

LinearSolve solve_columns(std::span<const double> z, double tau0, int k, const Columns& cols) {
  LMatrix a = LMatrix::Zero(k, k);
  LVector b = LVector::Zero(k);
  long double zz = 0;
  double g[kMaxColumns];
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (std::isnan(z[i])) continue;
    cols(static_cast<double>(i) * tau0, g);
    for (int r = 0; r < k; ++r) {
      b(r) += static_cast<long double>(g[r]) * z[i];
      for (int c = 0; c <= r; ++c)
        a(r, c) += static_cast<long double>(g[r]) * g[c];
    }
    zz += static_cast<long double>(z[i]) * z[i];
  }
  LinearSolve s;
  LVector d(k);
  for (int r = 0; r < k; ++r) {
    for (int c = 0; c < r; ++c)
      a(c, r) = a(r, c);
    d(r) = a(r, r) > 0 ? std::sqrt(a(r, r)) : 1.0L;
  }
  const LMatrix scaled = a.array() / (d * d.transpose()).array();
  const Eigen::FullPivLU<LMatrix> lu(scaled);
  s.sse = std::numeric_limits<long double>::infinity();  // a singular trial is never the best
  if (!lu.isInvertible()) return s;
  const LMatrix inv_scaled = lu.inverse();
  s.inverse = inv_scaled.array() / (d * d.transpose()).array();
  const LVector beta = s.inverse * b;
  s.sse = zz - beta.dot(b);
  s.beta.assign(beta.data(), beta.data() + k);
  s.ok = true;
  return s;
}

// The nonlinear parameter p minimizing the residual sum of squares of solve_columns(p) over
// [lo, hi] (log-spaced), a grid of 48 values then golden section between the best one's
// neighbours, in log p.
double search_parameter(const std::function<long double(double)>& sse, double lo, double hi) {
  constexpr int kGrid = 48;
  const double l0 = std::log(lo), l1 = std::log(hi);
  const auto at = [&](double lp) { return sse(std::exp(lp)); };
  int best = 0;
  long double best_sse = std::numeric_limits<long double>::infinity();
  for (int i = 0; i <= kGrid; ++i) {
    const long double v = at(l0 + (l1 - l0) * i / kGrid);
    if (v < best_sse) best_sse = v, best = i;
  }
  double a = l0 + (l1 - l0) * std::max(best - 1, 0) / kGrid;
  double b = l0 + (l1 - l0) * std::min(best + 1, kGrid) / kGrid;
  const double r = (std::sqrt(5.0) - 1) / 2;
  double c = b - r * (b - a), d = a + r * (b - a);
  long double fc = at(c), fd = at(d);
  for (int it = 0; it < 60 && b - a > 1e-9; ++it) {
    if (fc < fd) {
      b = d, d = c, fd = fc, c = b - r * (b - a), fc = at(c);
    } else {
      a = c, c = d, fc = fd, d = a + r * (b - a), fd = at(d);
    }
  }
  return std::exp((a + b) / 2);
}

// The columns of each model in its own parameters (the Jacobian of the model at `p` for the
// nonlinear ones, which at the optimum makes each estimate a linear functional to first order).
Columns model_jacobian(DriftModel m, const std::vector<double>& p) {
  switch (m) {
  case DriftModel::Linear:
    return [](double t, double* g) { g[0] = 1, g[1] = t; };
  case DriftModel::Quadratic:
    return [](double t, double* g) { g[0] = 1, g[1] = t, g[2] = t * t / 2; };
  case DriftModel::Log:
    return [a = p[0], b = p[1]](double t, double* g) {
      g[0] = std::log1p(b * t), g[1] = a * t / (b * t + 1), g[2] = 1;
    };
  case DriftModel::Diffusion:
    return [b = p[1], c = p[2]](double t, double* g) {
      g[0] = 1, g[1] = std::sqrt(t + c), g[2] = b / (2 * std::sqrt(t + c));
    };
  case DriftModel::None:
    break;
  }
  throw std::invalid_argument("drift model none has no columns");
}

// The estimates: linear models solved at once, log and diffusion after their search.
std::vector<double> estimate(std::span<const double> z, double tau0, DriftModel m) {
  const double span_s = static_cast<double>(z.size() - 1) * tau0;
  if (m == DriftModel::Log) {
    const auto cols = [](double b) {
      return [b](double t, double* g) { g[0] = std::log1p(b * t), g[1] = 1; };
    };
    const double b =
        search_parameter([&](double bb) { return solve_columns(z, tau0, 2, cols(bb)).sse; },
                         1e-3 / span_s, 1e4 / span_s);
    const LinearSolve s = solve_columns(z, tau0, 2, cols(b));
    if (!s.ok) throw std::invalid_argument("the log drift fit is singular");
    return {s.beta[0], b, s.beta[1]};
  }
  if (m == DriftModel::Diffusion) {
    const auto cols = [](double c) {
      return [c](double t, double* g) { g[0] = 1, g[1] = std::sqrt(t + c); };
    };
    const double c =
        search_parameter([&](double cc) { return solve_columns(z, tau0, 2, cols(cc)).sse; },
                         1e-4 * span_s, 1e3 * span_s);
    const LinearSolve s = solve_columns(z, tau0, 2, cols(c));
    if (!s.ok) throw std::invalid_argument("the diffusion drift fit is singular");
    return {s.beta[0], s.beta[1], c};
  }
  const int k = m == DriftModel::Linear ? 2 : 3;
  const LinearSolve s = solve_columns(z, tau0, k, model_jacobian(m, {}));
  if (!s.ok) throw std::invalid_argument("the drift fit is singular (too few valid samples)");
  return s.beta;
}

std::vector<std::string> parameter_names(DriftModel m) {
  switch (m) {
  case DriftModel::Linear:
    return {"offset", "drift"};
  case DriftModel::Quadratic:
    return {"phase_offset", "frequency_offset", "drift"};
  case DriftModel::Log:
  case DriftModel::Diffusion:
    return {"a", "b", "c"};
  case DriftModel::None:
    break;
  }
  return {};
}

// Each parameter's sigma: its weights on the samples, row p of (J^T J)^-1 J^T, put into the
// frequency-and-phase form of functional_variance.
std::vector<double> parameter_sigmas(std::span<const double> z, DataType type, double tau0,
                                     const DriftFit& fit) {
  const int k = static_cast<int>(fit.value.size());
  const Columns cols = model_jacobian(fit.model, fit.value);
  const LinearSolve s = solve_columns(z, tau0, k, cols);
  std::vector<double> sig(static_cast<std::size_t>(k), std::numeric_limits<double>::quiet_NaN());
  if (!s.ok) return sig;
  const std::size_t n = z.size();
  double g[kMaxColumns];
  for (int p = 0; p < k; ++p) {
    std::vector<double> w(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isnan(z[i])) continue;
      cols(static_cast<double>(i) * tau0, g);
      long double acc = 0;
      for (int c = 0; c < k; ++c)
        acc += s.inverse(p, c) * g[c];
      w[i] = static_cast<double>(acc);
    }
    std::vector<double> v, u;
    if (type == DataType::Rate) {
      // y_j = (x_{j+1} - x_j) / tau0: the phase points' own noise enters as (v_{i-1} - v_i)/tau0.
      v = w;
      u.assign(n + 1, 0.0);
      for (std::size_t i = 0; i <= n; ++i)
        u[i] = ((i > 0 ? v[i - 1] : 0.0) - (i < n ? v[i] : 0.0)) / tau0;
    } else {
      // x_i = tau0 sum_{j<i} y_j + e_i: a weight on x_i is tau0 on every y_j before it.
      u = w;
      v.assign(n - 1, 0.0);
      long double tail = 0;
      for (std::size_t j = n - 1; j-- > 0;) {
        tail += w[j + 1];
        v[j] = static_cast<double>(tail) * tau0;
      }
    }
    sig[static_cast<std::size_t>(p)] = std::sqrt(functional_variance(v, u, fit.noise));
  }
  return sig;
}

}  // namespace

DriftModel parse_drift_model(std::string_view text) {
  for (const DriftModel m : {DriftModel::None, DriftModel::Linear, DriftModel::Quadratic,
                             DriftModel::Log, DriftModel::Diffusion})
    if (text == to_string(m)) return m;
  throw std::invalid_argument("drift model '" + std::string(text) +
                              "': expected none, linear, quadratic, log or diffusion");
}

std::string_view to_string(DriftModel model) {
  switch (model) {
  case DriftModel::None:
    return "none";
  case DriftModel::Linear:
    return "linear";
  case DriftModel::Quadratic:
    return "quadratic";
  case DriftModel::Log:
    return "log";
  case DriftModel::Diffusion:
    return "diffusion";
  }
  return "none";
}

DriftModel drift_model_for(DriftModel asked, DataType type) {
  if (asked == DriftModel::Linear || asked == DriftModel::Quadratic)
    return type == DataType::Rate ? DriftModel::Linear : DriftModel::Quadratic;
  return asked;
}

double drift_model_value(const DriftFit& f, double t) {
  const std::vector<double>& p = f.value;
  switch (f.model) {
  case DriftModel::Linear:
    return p[0] + p[1] * t;
  case DriftModel::Quadratic:
    return p[0] + p[1] * t + p[2] * t * t / 2;
  case DriftModel::Log:
    return p[0] * std::log1p(p[1] * t) + p[2];
  case DriftModel::Diffusion:
    return p[0] + p[1] * std::sqrt(t + p[2]);
  case DriftModel::None:
    break;
  }
  return 0.0;
}

DriftFit fit_drift(std::span<const double> samples, DataType type, double tau0_s,
                   DriftModel model) {
  if (!(tau0_s > 0) || !std::isfinite(tau0_s))
    throw std::invalid_argument("drift: tau0_s must be finite and > 0");
  if (model == DriftModel::None) throw std::invalid_argument("drift: no model to fit");
  if ((model == DriftModel::Quadratic) != (type == DataType::Phase))
    throw std::invalid_argument(
        "drift model " + std::string(to_string(model)) + " does not fit " +
        (type == DataType::Phase ? "phase" : "rate") + " data (" +
        (type == DataType::Phase ? "phase data: quadratic" : "rate data: linear, log, diffusion") +
        ")");
  const auto valid =
      std::count_if(samples.begin(), samples.end(), [](double v) { return !std::isnan(v); });
  if (valid < 8)
    throw std::invalid_argument("drift: " + std::to_string(valid) +
                                " valid samples, at least 8 needed");
  DriftFit fit;
  fit.model = model;
  fit.fitted_to = type;
  fit.names = parameter_names(model);
  fit.n_used = valid;
  fit.value = estimate(samples, tau0_s, model);
  const std::vector<double> res = drift_residuals(samples, tau0_s, fit);
  fit.noise = fit_drift_noise(res, type, tau0_s);
  fit.sigma = parameter_sigmas(samples, type, tau0_s, fit);
  return fit;
}

void remove_drift(std::span<double> samples, double tau0_s, const DriftFit& fit) {
  // The model less its value at 0 and, for the phase parabola, less its linear part: the
  // frequency offset stays (every statistic removes it).
  const double at0 = drift_model_value(fit, 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (std::isnan(samples[i])) continue;
    const double t = static_cast<double>(i) * tau0_s;
    samples[i] -= fit.model == DriftModel::Quadratic ? fit.value[2] * t * t / 2
                                                     : drift_model_value(fit, t) - at0;
  }
}

std::vector<double> drift_residuals(std::span<const double> samples, double tau0_s,
                                    const DriftFit& fit) {
  std::vector<double> r(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    r[i] = samples[i] - drift_model_value(fit, static_cast<double>(i) * tau0_s);
  return r;
}

}  // namespace allanlot::kernels
