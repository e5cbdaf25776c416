// Diagnose's comparisons (docs/diagnose.md "Where", "Witnesses beside the Allan curve"): z tau by
// tau and its bands, the effective number of independent taus, the periodogram's line search and
// the Monte Carlo band of a model.
#include "kernels/diagnose/internal.hpp"

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/common/quantile.hpp"
#include "kernels/common/tasks.hpp"
#include "kernels/model/effective_taus.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace diagnose_detail {

Comparison compare(const Curve& cv, std::vector<double> model, const std::vector<double>& edf,
                   double alpha_tau) {
  Comparison out;
  const std::size_t p = cv.size();
  out.z.resize(p);
  out.p_value.resize(p);
  out.significant.resize(p);
  double s = 0.0;
  for (std::size_t i = 0; i < p; ++i) {
    const double ratio = cv.y[i] / model[i];
    out.z[i] = std::log(ratio) / std::sqrt(2.0 / edf[i]);
    s += out.z[i] * out.z[i];
    const double cdf = chi2_cdf(edf[i] * ratio, edf[i]);
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

McBand monte_carlo(const ChannelSpec& spec, const Curve& cv, const std::vector<double>& model,
                   const std::vector<double>& edf, int replicas, std::uint64_t seed, int threads) {
  McBand out;
  out.replicas = replicas;
  const std::size_t p = cv.size();
  if (replicas <= 0) return out;
  const auto n = static_cast<std::size_t>(cv.n_samples);
  ChannelSpec noise = spec;
  noise.steps.clear();
  // Per replica: the avar of the noise (its gap is judged, as the record without its steps is)
  // and, with steps, of the noise plus the model's jumps (the band drawn around the model's
  // curve for the record as measured: a jump's share and its cross term with the noise).
  std::vector<std::vector<double>> avar(static_cast<std::size_t>(replicas));
  std::vector<std::vector<double>> drawn(spec.steps.empty() ? 0 : avar.size());
  ExceptionCollector errors;
  // One simulation plan a thread (simulate_channel's, kept): the flicker filter's spectrum, an
  // FFT of twice the record, is made once a thread rather than once a replica (a sixth of the
  // replicas' time on 10^6 samples); a plan gives the same samples as a fresh one. The threads
  // are those of the team that runs the replicas: this call's own, or the enclosing region's
  // when the replicas are its tasks (for_each_index).
#ifdef _OPENMP
  const int team = omp_in_parallel() ? omp_get_num_threads() : threads;
#else
  const int team = 1;
#endif
  std::vector<std::unique_ptr<SimulationPlan>> plans(static_cast<std::size_t>(std::max(team, 1)));
  // One replica per index, each written by one thread into its own row, with its own Philox
  // stream (the replica index): the band does not depend on the thread count.
  for_each_index(replicas, threads, [&](std::int64_t r) {
    errors.run([&] {
#ifdef _OPENMP
      auto& plan = plans[static_cast<std::size_t>(omp_get_thread_num())];
#else
      auto& plan = plans.front();
#endif
      if (!plan) plan = std::make_unique<SimulationPlan>(n);
      std::vector<double> buf(n);
      plan->run(noise, seed, static_cast<std::uint64_t>(r), buf, 1);
      const auto avar_of = [&](std::vector<double>& row) {
        const PhaseData ph = phase_from_rate(buf, spec.rate_hz, 1);
        const StatResult s = compute(Stat::Oadev, ph, cv.m, 1);
        if (s.size() != p) throw std::logic_error("diagnose: replica tau grid differs");
        row.resize(p);
        for (std::size_t i = 0; i < p; ++i)
          row[i] = s.dev[i] * s.dev[i];
      };
      avar_of(avar[static_cast<std::size_t>(r)]);
      if (spec.steps.empty()) return;
      add_steps(buf, spec.steps, spec.rate_hz);
      avar_of(drawn[static_cast<std::size_t>(r)]);
    });
  });
  errors.rethrow();
  const auto& band_rows = spec.steps.empty() ? avar : drawn;
  out.avar_lo.resize(p);
  out.avar_median.resize(p);
  out.avar_hi.resize(p);
  std::vector<double> col(static_cast<std::size_t>(replicas));
  for (std::size_t i = 0; i < p; ++i) {
    for (std::size_t r = 0; r < col.size(); ++r)
      col[r] = band_rows[r][i];
    std::sort(col.begin(), col.end());
    // Thresholds for a fresh record, as the verdict's: one of the model lies inside the band at
    // a tau 90 % of the time (the sample quantiles of 30 replicas, 84 %).
    out.avar_lo[i] = exceedance_quantile_sorted(col, 0.05);
    out.avar_median[i] = quantile_sorted(col, 0.5);
    out.avar_hi[i] = exceedance_quantile_sorted(col, 0.95);
  }
  // The replicas' gaps use the model's edf, as the measurement's gap against this model does,
  // so that they are draws of the very statistic reported under the hypothesis that the model
  // is right.
  for (const auto& row : avar)
    out.gaps.push_back(diagnose_gap(row, model, edf));
  std::vector<double> g = out.gaps;
  std::sort(g.begin(), g.end());
  out.gap_median = quantile_sorted(g, 0.5);
  // The verdict's threshold: a record of this model exceeds it 5 % of the time (the sample's
  // own 95 % quantile, from 30 replicas, 7.9 %).
  out.gap_p95 = exceedance_quantile_sorted(g, kGapNoiseQuantile);
  return out;
}

Eigen::MatrixXd tau_correlation(const Curve& cv) {
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
  if (!has_terms(r.status) || fit.covariance().rows() != static_cast<Eigen::Index>(p)) return {};
  const Eigen::MatrixXd& s = fit.covariance();
  const Eigen::VectorXd sd = s.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!s.allFinite() || !(sd.minCoeff() > 0.0)) return {};
  return sd.cwiseInverse().asDiagonal() * s * sd.cwiseInverse().asDiagonal();
}

// Satterthwaite's effective number of independent taus from the model covariance of the
// estimates (see the header). The eq. (3) fit to the measurement supplies the covariance.
double effective_taus(const Curve& cv) {
  return effective_taus(cv, tau_correlation(cv));
}

double effective_taus(const Curve& cv, const Eigen::MatrixXd& corr) {
  if (const double n_eff = effective_taus_of(corr); n_eff > 0.0) return n_eff;
  // Fallback: one independent estimate per octave of tau (overlapping estimates an octave or
  // more apart are correlated well below 0.5 for the common noises).
  return std::clamp(std::log2(cv.tau.back() / cv.tau.front()) + 1.0, 1.0,
                    static_cast<double>(cv.size()));
}

double ring_median(const PsdResult& psd, std::int64_t k, std::int64_t lo, std::int64_t hi,
                   std::vector<double>& buf) {
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  buf.clear();
  for (std::int64_t j = std::max<std::int64_t>(k - hi, 1); j <= std::min(k + hi, kmax); ++j)
    if (std::abs(j - k) >= lo) buf.push_back(psd.psd[static_cast<std::size_t>(j)]);
  if (buf.empty()) return 0.0;
  const auto mid = buf.begin() + static_cast<std::ptrdiff_t>(buf.size() / 2);
  std::nth_element(buf.begin(), mid, buf.end());
  return *mid;
}

namespace {

constexpr std::int64_t kMinBin = 32, kHalf = 64, kCore = 3, kEdge = 8;

struct Peak {
  std::int64_t k = -1;
  double ratio = 0.0, bg = 0.0;
  std::int64_t n_searched = 0;
};

// The bin of largest periodogram over background in [f_lo_hz, f_hi_hz], 4 bins or more from
// each frequency in `known` and `wide_hz` bins or more from each in `wide`; `medians` as
// line_backgrounds gives them.
Peak strongest_bin(const PsdResult& psd, std::span<const double> medians,
                   std::span<const double> known, std::span<const double> wide, double wide_hz,
                   double f_lo_hz, double f_hi_hz) {
  Peak out;
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  for (std::int64_t k = kMinBin; k <= kmax - kEdge; ++k) {
    const double f = static_cast<double>(k) * psd.df_hz;
    if (f < f_lo_hz || f > f_hi_hz) continue;
    const auto near = [&](std::span<const double> fs, double radius) {
      return std::any_of(fs.begin(), fs.end(),
                         [&](double fk) { return std::abs(f - fk) <= radius; });
    };
    if (near(known, 4.0 * psd.df_hz) || near(wide, wide_hz)) continue;
    ++out.n_searched;
    const double median = medians[static_cast<std::size_t>(k)];
    if (std::isnan(median)) continue;
    const double bg = median / std::numbers::ln2;
    if (!(bg > 0.0)) continue;
    const double ratio = psd.psd[static_cast<std::size_t>(k)] / bg;
    if (ratio > out.ratio) {
      out.ratio = ratio;
      out.bg = bg;
      out.k = k;
    }
  }
  return out;
}

// The line's frequency, power and their Cramer-Rao bounds at the peak bin.
void describe_line(const PsdResult& psd, double n_seconds, const Peak& pk, SpectralLine& out) {
  // Peak frequency by a parabola through the log periodogram at the peak and its neighbours
  // (the Hann main lobe is close to Gaussian in shape, whose log is a parabola).
  const auto at = [&](std::int64_t k) { return std::log(psd.psd[static_cast<std::size_t>(k)]); };
  const double lm = at(pk.k - 1), l0 = at(pk.k), lp = at(pk.k + 1);
  const double den = lm - 2.0 * l0 + lp;
  const double delta = den < 0.0 ? std::clamp(0.5 * (lm - lp) / den, -0.5, 0.5) : 0.0;
  out.frequency_hz = (static_cast<double>(pk.k) + delta) * psd.df_hz;
  // The line's power: the periodogram above the background over the main lobe and the first
  // side lobes (the Welch normalization makes sum P df the mean square, so a line of
  // amplitude A contributes A^2 / 2).
  double power = 0.0;
  for (std::int64_t j = pk.k - kCore; j <= pk.k + kCore; ++j)
    power += (psd.psd[static_cast<std::size_t>(j)] - pk.bg) * psd.df_hz;
  out.amplitude = std::sqrt(2.0 * std::max(power, 0.0));
  // Cramer-Rao bound of a tone's frequency in locally white noise of one-sided density S1 over
  // a record of T seconds (Rife & Boorstyn, IEEE Trans. Inf. Theory 20(5), 1974):
  // var(omega) = 24 sigma^2 / (A^2 N^3) per sample, sigma^2 = S1 fs / 2, hence
  // sigma_f = sqrt(3 S1 / (A^2 T^3)) / pi.
  // The amplitude's: var(A) = 2 sigma^2 / N per sample (same reference), i.e. S1 / T.
  out.amplitude_sigma = std::sqrt(pk.bg / n_seconds);
  if (out.amplitude > 0.0)
    out.sigma_hz = std::sqrt(3.0 * pk.bg /
                             (out.amplitude * out.amplitude * n_seconds * n_seconds * n_seconds)) /
                   std::numbers::pi;
}

}  // namespace

// Each bin's background for the line search: the median of the bins kCore + 1 to kHalf away on
// both sides (a symmetric window, so that the median of a monotone background is its central
// value), NaN where fewer than 8 bins are there. It depends on the periodogram alone, so a
// diagnosis computes it once for all its rounds (a fifth of a z gyroscope's diagnosis went to
// recomputing it).
std::vector<double> line_backgrounds(const PsdResult& psd, int threads) {
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  std::vector<double> out(psd.size(), std::numeric_limits<double>::quiet_NaN());
  // Each bin's median is its own (a selection over its window): split over the threads in blocks,
  // each with its window's buffer, the same numbers for any thread count.
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> window;
#pragma omp for schedule(static)
    for (std::int64_t k = kMinBin; k <= kmax - kEdge; ++k) {
      const double median =
          ring_median(psd, k, kCore + 1, std::min({kHalf, k - 1, kmax - k}), window);
      if (window.size() >= 8) out[static_cast<std::size_t>(k)] = median;
    }
  }
  return out;
}

// Line search on a periodogram (see find_spectral_line). A significant peak wider than a line
// is no sinusoid's witness: the first such is noted and fitted as a resonance (wide_hz,
// narrowband), and the search goes on without the bins within the far ring of it, at most
// kMaxWide times; the far rings of `known_wide` (the model's resonances) are left out from the
// start.
SpectralLine search_line(const PsdResult& psd, std::span<const double> medians, double n_seconds,
                         std::span<const double> known, std::span<const double> known_wide,
                         double false_alarm, double f_lo_hz, double f_hi_hz) {
  constexpr int kMaxWide = 4;
  SpectralLine out;
  out.searched = true;
  out.resolution_hz = psd.df_hz;
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  if (kmax - kEdge <= kMinBin) {
    out.searched = false;
    return out;
  }
  std::vector<double> wide(known_wide.begin(), known_wide.end());
  for (int attempt = 0; attempt <= kMaxWide; ++attempt) {
    const Peak pk = strongest_bin(psd, medians, known, wide,
                                  static_cast<double>(kFarRing) * psd.df_hz, f_lo_hz, f_hi_hz);
    if (pk.k < 0 || pk.n_searched == 0) return out;
    out.threshold = std::log(static_cast<double>(pk.n_searched) / false_alarm);
    out.peak_ratio = pk.ratio;
    out.found = pk.ratio > out.threshold;
    if (!out.found || !wider_than_a_line(psd, pk.k)) {
      describe_line(psd, n_seconds, pk, out);
      return out;
    }
    if (out.wide_hz == 0.0) {
      out.wide_hz = static_cast<double>(pk.k) * psd.df_hz;
      out.narrowband = fit_narrowband(psd, pk.k, false_alarm);
    }
    wide.push_back(static_cast<double>(pk.k) * psd.df_hz);
  }
  out.found = false;
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

}  // namespace diagnose_detail

using namespace diagnose_detail;

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
  const int threads = resolve_threads(nthreads);
  const PsdResult psd = full_periodogram(rate, rate_hz, threads);
  return search_line(psd, line_backgrounds(psd, threads),
                     static_cast<double>(rate.size() - rate.size() % 2) / rate_hz, known_hz, {},
                     false_alarm);
}

}  // namespace allanlot::kernels
