#include "kernels/plan/record_fit.hpp"

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <stdexcept>
#include <string>

namespace allanlot::kernels {

StatResult record_curve(std::span<const double> rate, double rate_hz, int threads) {
  const PhaseData phase = phase_from_rate(rate, rate_hz, threads);
  const std::int64_t m_max = max_m(Stat::Oadev, phase.n_points());
  if (m_max < 8)
    throw std::invalid_argument("record too short (" + std::to_string(rate.size()) +
                                " samples); need at least 3 octaves of tau (33 samples)");
  TauGridSpec grid;
  grid.kind = TauGridKind::Log;
  grid.per_decade = kPlanTausPerDecade;
  StatResult oadev = compute(Stat::Oadev, phase, make_m_list(grid, m_max), threads);
  add_confidence(Stat::Oadev, phase, oadev, kDefaultConfidence, threads);
  return oadev;
}

FitResult fit_record(std::span<const double> rate, double rate_hz, Eq3Fit& fitter, int threads) {
  const StatResult oadev = record_curve(rate, rate_hz, threads);
  fitter.set_threads(threads);
  return fitter.fit(oadev, 1.0 / rate_hz, static_cast<std::int64_t>(rate.size()));
}

std::vector<FitResult> simulated_fits(const ChannelSpec& spec, std::int64_t n_samples, int replicas,
                                      std::uint64_t seed, int threads) {
  SimulationPlan plan(static_cast<std::size_t>(n_samples));
  Eq3Fit fitter;  // one curve shape: the covariance basis is built once
  std::vector<double> y(static_cast<std::size_t>(n_samples));
  std::vector<FitResult> fits;
  for (int r = 0; r < replicas; ++r) {
    plan.run(spec, seed, static_cast<std::uint64_t>(r), y, threads);
    fits.push_back(fit_record(y, spec.rate_hz, fitter, threads));
  }
  return fits;
}

}  // namespace allanlot::kernels
