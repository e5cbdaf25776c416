#include "src/pipeline/channel.hpp"

#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "src/pipeline/channel_fit.hpp"
#include "src/pipeline/channel_gaps.hpp"
#include "src/pipeline/channel_powerlaw.hpp"
#include "src/pipeline/channel_quality.hpp"
#include "src/pipeline/spectrum.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace allanlot::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void add_note(io::ChannelResult& r, const std::string& note) {
  r.notes += (r.notes.empty() ? "" : "; ") + note;
}

// Samples near the top of double's range (|x| ~ 1e300) square to infinity: fail the channel
// naming the cause rather than write inf or let the fit reject it.
void require_finite(kernels::Stat s, const kernels::StatResult& r) {
  for (std::size_t i = 0; i < r.size(); ++i)
    if (!std::isfinite(r.dev[i])) {
      char tau[32];
      std::snprintf(tau, sizeof tau, "%.6g", r.tau_s[i]);
      throw std::invalid_argument(std::string(kernels::stat_name(s)) + " is not finite at tau " +
                                  tau +
                                  " s: the samples' differences overflow double precision "
                                  "(rescale them, e.g. with a scale attribute)");
    }
}

// The caches one channel's statistics share: noise identification (lag-1 levels) and
// OADEV's sums, which are TOTDEV's inner sums.
struct StatCaches {
  kernels::Lag1Cache noise_id;
  kernels::SumCache sums;
};

kernels::StatResult compute_stat(kernels::Stat s, const kernels::PhaseData& phase,
                                 const ChannelOptions& opt, StatCaches& caches,
                                 const kernels::StatResult* mdev) {
  const auto ms =
      kernels::stat_m_list(opt.grid, s, kernels::max_m(s, phase.n_points()), phase.n_points());
  // TDEV is derived from MDEV when both are requested (tau/sqrt(3) times the same sum, SP1065
  // eq. (16)) instead of summing the same third differences twice.
  kernels::StatResult r = (s == kernels::Stat::Tdev && mdev && mdev->m == ms)
                              ? kernels::tdev_from_mdev(*mdev)
                              : kernels::compute(s, phase, ms, opt.threads, &caches.sums);
  require_finite(s, r);
  kernels::add_confidence(s, phase, r, opt.confidence, opt.threads, &caches.noise_id);
  return r;
}

// OADEV and OHDEV at their common m from one sweep (kernels::prime_second_third) when both are
// asked for: the statistics then take their sums from the cache, with the same bits.
void share_second_third(const kernels::PhaseData& phase, const ChannelOptions& opt,
                        StatCaches& caches) {
  const auto asked = [&](kernels::Stat s) {
    return std::find(opt.stats.begin(), opt.stats.end(), s) != opt.stats.end();
  };
  if (phase.has_gaps() || !asked(kernels::Stat::Oadev) || !asked(kernels::Stat::Ohdev)) return;
  const auto list = [&](kernels::Stat s) {
    return kernels::stat_m_list(opt.grid, s, kernels::max_m(s, phase.n_points()), phase.n_points());
  };
  const std::vector<std::int64_t> a = list(kernels::Stat::Oadev), h = list(kernels::Stat::Ohdev);
  std::vector<std::int64_t> both;
  std::set_intersection(a.begin(), a.end(), h.begin(), h.end(), std::back_inserter(both));
  kernels::prime_second_third(phase, both, opt.threads, caches.sums);
}

// Every requested statistic into result.stats; returns the overlapping Allan curve the fit and
// the cross-check need (computed for them when not requested: fit/ is written whatever --stats
// says, docs/formats.md), or nullopt when neither runs. Throws std::invalid_argument when no
// statistic has a single tau.
std::optional<kernels::StatResult> compute_stats(io::ChannelResult& result,
                                                 const kernels::PhaseData& phase,
                                                 const ChannelOptions& opt) {
  StatCaches caches;
  share_second_third(phase, opt, caches);
  bool any_row = false;
  const kernels::StatResult* mdev = nullptr;
  std::optional<kernels::StatResult> oadev;
  result.stats.reserve(opt.stats.size());  // `mdev` points into it: no reallocation
  for (const kernels::Stat s : opt.stats) {
    if (phase.has_gaps() && !kernels::supports_gaps(s)) {
      // Skipped, not failed: the channel's other statistics stand, and the note says why.
      add_note(result, std::string(kernels::stat_name(s)) +
                           " not computed: it cannot run on data with gaps (" +
                           std::to_string(phase.n_gaps) + " missing samples)");
      continue;
    }
    kernels::StatResult r = compute_stat(s, phase, opt, caches, mdev);
    any_row = any_row || r.size() > 0;
    result.stats.emplace_back(std::string(kernels::stat_name(s)), std::move(r));
    if (s == kernels::Stat::Mdev) mdev = &result.stats.back().second;
    if (s == kernels::Stat::Oadev) oadev = result.stats.back().second;
  }
  if (!any_row) {
    result.stats.clear();
    throw std::invalid_argument("too short for any tau of the requested statistics (" +
                                std::to_string(result.n_samples) + " samples)");
  }
  if (!opt.fit && !opt.psd) return std::nullopt;
  if (!oadev) oadev = compute_stat(kernels::Stat::Oadev, phase, opt, caches, nullptr);
  // Without one tau of the overlapping Allan curve there is nothing to fit or cross-check: a
  // failure with its reason, not "ok" with empty tables.
  if (oadev->size() == 0)
    throw std::invalid_argument(
        "too short for the fit and the PSD (" + std::to_string(result.n_samples) +
        " samples: the overlapping Allan deviation has no tau; --no-fit --no-psd analyses the "
        "other statistics alone)");
  return oadev;
}

// Largest, smallest and mean of the samples (gaps left out), for the head of a Stable32 table
// (docs/formats.md); the mean summed in long double, in sample order, so that it does not
// depend on the thread count.
void summarize_samples(io::ChannelResult& r, std::span<const double> samples) {
  long double sum = 0;
  std::int64_t n = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : samples) {
    if (std::isnan(v)) continue;
    sum += v;
    ++n;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (n == 0) return;
  r.data_min = lo;
  r.data_max = hi;
  r.data_mean = static_cast<double>(sum / static_cast<long double>(n));
}

// The stages after the samples are read; throws std::exception on a numerical precondition.
void run_stages(ChannelAnalysis& a, const io::ChannelInfo& channel,
                kernels::LargeVector<double>& samples, const ChannelOptions& opt) {
  const auto t_kernels = Clock::now();
  summarize_samples(a.result, samples);
  // The screen sees the samples as read, before the phase replaces them (docs/quality.md).
  a.result.quality = screen_channel(channel, samples, opt.threads);
  edit_channel(a.result, channel, samples, opt.edit);
  kernels::PhaseData phase = channel_phase(a.result, channel, samples, opt.gaps, opt.threads);
  dynamic_channel(a.result, channel, {samples.data(), samples.size()}, opt.edit, opt.threads);
  samples = kernels::LargeVector<double>{};  // the phase replaces the samples
  const std::optional<kernels::StatResult> oadev = compute_stats(a.result, phase, opt);
  a.times.kernels += seconds_since(t_kernels);
  if (!oadev) return;
  std::array<kernels::TermFit, kernels::kNumTerms> allan_terms{};
  bool have_allan_terms = false;
  if (opt.fit && uses_powerlaw(opt.noise_model, a.result)) {
    // A clock: the power-law levels instead of eq. (3) (docs/clocks.md).
    const auto t_fit = Clock::now();
    a.result.powerlaw = powerlaw_channel(a.result, phase, *oadev, opt.confidence, opt.threads);
    a.times.fit += seconds_since(t_fit);
  } else if (opt.fit) {
    const auto t_fit = Clock::now();
    a.result.fit = fit_channel(*oadev, phase.tau0_s, phase.n_points() - 1, a.result.units,
                               opt.lowpass, &allan_terms, opt.threads);
    have_allan_terms = kernels::has_terms(a.result.fit->status);
    if (opt.defer_model && opt.model.enabled && a.result.fit->status == kernels::FitStatus::PoorFit)
      a.deferred = std::make_shared<DeferredModel>(DeferredModel{phase, *oadev});
    else
      model_poor_fit(a.result, phase, *oadev, opt.model, opt.threads);
    a.times.fit += seconds_since(t_fit);
  }
  if (opt.psd) {
    const auto t_psd = Clock::now();
    add_spectrum(a.result, phase, *oadev, opt.threads, have_allan_terms ? &allan_terms : nullptr);
    a.times.psd += seconds_since(t_psd);
  }
}

}  // namespace

io::ChannelResult describe_channel(const io::ChannelInfo& channel) {
  io::ChannelResult r;
  r.path = channel.path;
  r.units = channel.units;
  r.sample_rate_hz = channel.sample_rate_hz;
  r.n_samples = channel.n_samples;
  r.data_type = channel.data_type == kernels::DataType::Rate ? "rate" : "phase";
  // Said where nobody said it: neither the file nor --data-type (docs/formats.md).
  if (channel.data_type_default) r.data_type += " (default)";
  return r;
}

ChannelAnalysis analyze_channel(const io::ChannelInfo& channel,
                                kernels::LargeVector<double> samples, const ChannelOptions& opt) {
  ChannelAnalysis a;
  a.result = describe_channel(channel);
  try {
    run_stages(a, channel, samples, opt);
  } catch (const std::exception& e) {
    a.result.status = io::ChannelStatus::failed(e.what());
  } catch (...) {
    a.result.status = io::ChannelStatus::failed("unexpected error");
  }
  return a;
}

void model_deferred(ChannelAnalysis& a, const ChannelOptions& opt, int threads) {
  if (!a.deferred) return;
  const auto t_fit = Clock::now();
  try {
    model_poor_fit(a.result, a.deferred->phase, a.deferred->oadev, opt.model, threads);
  } catch (const std::exception& e) {
    a.result.status = io::ChannelStatus::failed(e.what());
  } catch (...) {
    a.result.status = io::ChannelStatus::failed("unexpected error");
  }
  a.deferred.reset();
  a.times.fit += seconds_since(t_fit);
}

}  // namespace allanlot::pipeline
