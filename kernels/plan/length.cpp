#include "kernels/plan/length.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/plan/sequential.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace allanlot::kernels {
namespace {

constexpr std::int64_t kMinSamples = 33;  // 3 octaves of tau (record_fit.hpp)

// The power law (S_y ~ f^alpha) of the term with the largest share of eq. (3) at tau. The ramp
// has no edf of its own (alpha -4 makes the Allan variance diverge); its neighbour, the random
// walk, stands in.
int dominant_alpha(const NoiseTerms& t, double tau) {
  const std::array<double, kNumTerms> g = eq3_regressors(tau);
  const std::array<double, kNumTerms> share = {t.R * t.R * g[0], t.K * t.K * g[1], t.B * t.B * g[2],
                                               t.N * t.N * g[3], t.Q * t.Q * g[4]};
  constexpr std::array<int, kNumTerms> alpha = {-2, -2, -1, 0, 2};
  const auto i = std::max_element(share.begin(), share.end()) - share.begin();
  return alpha[static_cast<std::size_t>(i)];
}

double relative_sigma(const ChannelSpec& spec, Term term, std::int64_t n, Eq3Fit& fitter) {
  const FitResult f = predicted_fit(spec, n, fitter);
  if (!has_terms(f.status)) return std::numeric_limits<double>::infinity();
  return f[term].sigma / coefficient(spec.terms, term);
}

}  // namespace

ExpectedCurve expected_curve(const ChannelSpec& spec, std::int64_t n_samples) {
  if (n_samples < kMinSamples)
    throw std::invalid_argument("plan: a record of " + std::to_string(n_samples) +
                                " samples is too short; need at least 33");
  TauGridSpec grid;
  grid.kind = TauGridKind::Log;
  grid.per_decade = kPlanTausPerDecade;
  const std::int64_t n_phase = n_samples + 1;
  const FiniteDifferenceKind oavar{2, true, false};
  ExpectedCurve c;
  for (const std::int64_t m : make_m_list(grid, max_m(Stat::Oadev, n_phase))) {
    const double tau = static_cast<double>(m) / spec.rate_hz;
    c.m.push_back(m);
    c.n.push_back(n_phase - 2 * m);
    c.tau_s.push_back(tau);
    c.avar.push_back(model_avar_sampled(spec, m, n_samples));
    c.edf.push_back(edf_greenhall(dominant_alpha(spec.terms, tau), oavar, m, n_phase));
  }
  return c;
}

FitResult predicted_fit(const ChannelSpec& spec, std::int64_t n_samples, Eq3Fit& fitter) {
  const ExpectedCurve c = expected_curve(spec, n_samples);
  FitInput in;
  in.tau_s = c.tau_s;
  in.values = c.avar;
  in.n = c.n;
  in.edf = c.edf;
  in.tau0_s = 1.0 / spec.rate_hz;
  in.n_samples = n_samples;
  return fitter.fit(in);
}

LengthTarget limit_target(Term term, double limit, bool is_max, double margin, double confidence,
                          double* value) {
  if (!(margin > 0.0 && margin < 1.0) || !(limit > 0.0) || !(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("plan: need a limit > 0, 0 < margin < 1 and 0 < confidence < 1");
  *value = limit * (is_max ? 1.0 - margin : 1.0 + margin);
  LengthTarget t;
  t.term = term;
  t.relative = margin / (is_max ? 1.0 - margin : 1.0 + margin);
  t.quantile = normal_quantile(0.5 + 0.5 * confidence) + normal_quantile(confidence);
  return t;
}

LengthPlan plan_length(const ChannelSpec& spec, const LengthTarget& target,
                       std::int64_t max_samples, Eq3Fit& fitter) {
  const double value = coefficient(spec.terms, target.term);
  if (!(value > 0.0))
    throw std::invalid_argument(std::string("plan: the model's ") +
                                std::string(term_name(target.term)) +
                                " is 0; no record length measures it to a relative precision");
  if (!(target.relative > 0.0) || !(target.quantile > 0.0))
    throw std::invalid_argument("plan: the target precision and quantile must be > 0");
  const auto meets = [&](std::int64_t n, double& rel) {
    rel = relative_sigma(spec, target.term, n, fitter);
    return target.quantile * rel <= target.relative;
  };
  LengthPlan p;
  double rel = 0.0;
  std::int64_t lo = 0, hi = kMinSamples;
  while (!meets(hi, rel)) {
    lo = hi;
    if (hi >= max_samples) {
      p.n_samples = hi;
      p.relative_sigma = rel;
      p.duration_s = static_cast<double>(hi) / spec.rate_hz;
      return p;
    }
    hi = std::min(2 * hi, max_samples);
  }
  double rel_hi = rel;
  // Bisection in log n between a length that fails (lo) and one that meets the target (hi).
  while (lo > 0 && static_cast<double>(hi) > 1.01 * static_cast<double>(lo) && hi - lo > 1) {
    const auto mid =
        static_cast<std::int64_t>(std::llround(std::sqrt(static_cast<double>(lo) * hi)));
    if (meets(mid, rel)) {
      hi = mid;
      rel_hi = rel;
    } else {
      lo = mid;
    }
  }
  p.reached = true;
  p.n_samples = hi;
  p.duration_s = static_cast<double>(hi) / spec.rate_hz;
  p.relative_sigma = rel_hi;
  // Where the term makes at least half the Allan variance: the taus that measure it.
  const ExpectedCurve c = expected_curve(spec, hi);
  for (std::size_t i = 0; i < c.tau_s.size(); ++i) {
    const double part =
        value * value * eq3_regressors(c.tau_s[i])[static_cast<std::size_t>(target.term)];
    if (part < 0.5 * c.avar[i]) continue;
    if (p.tau_lo_s == 0.0) p.tau_lo_s = c.tau_s[i];
    p.tau_hi_s = c.tau_s[i];
  }
  return p;
}

}  // namespace allanlot::kernels
