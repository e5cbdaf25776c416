// The measurement diagnose compares models with: the overlapping Allan variance of the record on
// a log grid, with the Greenhall-Riley edf of each tau and the unbiased logarithm of each
// estimate (Curve).
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/diagnose/internal.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {

using namespace diagnose_detail;

Curve diagnose_detail::curve_of(const StatResult& oadev, double rate_hz, std::int64_t n_samples) {
  Curve cv;
  cv.tau0 = 1.0 / rate_hz;
  cv.n_samples = n_samples;
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    const double y = oadev.dev[i] * oadev.dev[i];
    if (!(y > 0.0) || !(oadev.edf[i] > 0.0)) continue;  // ln 0: nothing to compare
    cv.m.push_back(oadev.m[i]);
    cv.n.push_back(oadev.n[i]);
    cv.tau.push_back(oadev.tau_s[i]);
    cv.y.push_back(y);
    cv.edf.push_back(oadev.edf[i]);
  }
  if (cv.size() == 0) return cv;
  // The measured curve's own edf (from its noise identification) serves only the eq. (3) fit
  // behind n_eff, capped at what the averages allow: where a line or the last few averages make
  // the identified alpha +1 or +2 it would exceed the number of averages 10-200 fold.
  // Every z uses the edf of the model under test instead (model_edf).
  prepare_edf(cv);
  for (std::size_t i = 0; i < cv.size(); ++i)
    cv.edf[i] = std::min(cv.edf[i], cv.edf_cap[i]);
  use_edf(cv, cv.edf);
  return cv;
}

// The measurement: overlapping Allan variance on a log grid with its Greenhall-Riley edf, and
// the unbiased logarithm of each estimate with its variance (Curve).
Curve diagnose_detail::measure(std::span<const double> rate, double rate_hz,
                               const DiagnoseOptions& opt, int threads) {
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
  Curve cv = curve_of(oadev, rate_hz, static_cast<std::int64_t>(rate.size()));
  if (cv.size() < 4)
    throw std::invalid_argument("diagnose: fewer than 4 taus with a non-zero Allan variance");
  return cv;
}

}  // namespace allanlot::kernels
