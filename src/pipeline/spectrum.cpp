#include "src/pipeline/spectrum.hpp"

#include "src/pipeline/channel_fit.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace allanlot::pipeline {

kernels::LargeVector<double> rate_from_phase(const kernels::PhaseData& phase) {
  const kernels::LargeVector<double>& x = phase.x;
  kernels::LargeVector<double> rate(x.size() - 1);  // every element is written below
  const double rate_hz = 1.0 / phase.tau0_s;
  for (std::size_t k = 0; k + 1 < x.size(); ++k)
    rate[k] = phase.clean(static_cast<std::int64_t>(k), static_cast<std::int64_t>(k) + 1)
                  ? (x[k + 1] - x[k]) * rate_hz
                  : std::nan("");
  return rate;
}

io::CrosscheckRecord crosscheck_record(const kernels::StatResult& oadev,
                                       const kernels::AvarPsdResult& from_psd) {
  io::CrosscheckRecord cc;
  cc.tau = oadev.tau_s;
  cc.avar_psd = from_psd.avar;
  cc.valid = from_psd.valid;
  double worst = -1.0;
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    const double avar = oadev.dev[i] * oadev.dev[i];
    cc.avar_time.push_back(avar);
    cc.ratio.push_back(from_psd.avar[i] / avar);
    if (from_psd.valid[i] && std::isfinite(cc.ratio.back()) && cc.ratio.back() > 0.0 &&
        std::abs(std::log10(cc.ratio.back())) > worst) {
      worst = std::abs(std::log10(cc.ratio.back()));
      cc.worst_tau = oadev.tau_s[i];
    }
  }
  cc.max_abs_log10_ratio = worst >= 0.0 ? worst : std::nan("");
  cc.valid_tau_range = {from_psd.tau_valid_min, from_psd.tau_valid_max};
  return cc;
}

namespace {

io::PsdRecord psd_record(const kernels::PsdResult& psd) {
  const kernels::BinnedPsd binned = kernels::log_bin(psd);
  io::PsdRecord pr;
  pr.method = "welch, hann window, 50% overlap, segment length " +
              std::to_string(psd.segment_length) + ", " + std::to_string(psd.n_segments) +
              " segments (" + std::to_string(psd.n_skipped) + " skipped for gaps), log-binned";
  pr.f = binned.f_hz;
  pr.psd = binned.psd;
  pr.edf = binned.edf;
  pr.n_avg = binned.n_avg;
  return pr;
}

}  // namespace

void add_spectrum(io::ChannelResult& result, kernels::PhaseData& phase,
                  const kernels::StatResult& oadev, int threads,
                  const std::array<kernels::TermFit, kernels::kNumTerms>* allan_terms) {
  const double rate_hz = 1.0 / phase.tau0_s;
  const kernels::LargeVector<double> rate = rate_from_phase(phase);
  // The phase is not needed after this point: freeing it here keeps a channel's peak at the
  // phase plus one working array at every stage.
  phase = kernels::PhaseData{};
  kernels::PsdResult psd;
  try {
    psd = kernels::welch_psd(rate, rate_hz, threads);
  } catch (const std::invalid_argument& e) {
    result.notes += (result.notes.empty() ? "" : "; ") + std::string("no PSD: ") + e.what();
    return;
  }
  result.psd = psd_record(psd);
  // eq. (3) in the PSD domain for the channels eq. (3) describes; a clock's power-law levels
  // (powerlaw/) have no PSD-domain counterpart here.
  if (!result.powerlaw) result.psd_fit = psd_fit_channel(psd, result.units, allan_terms, threads);
  result.crosscheck =
      crosscheck_record(oadev, kernels::avar_from_psd(psd, oadev.tau_s, {}, threads));
}

}  // namespace allanlot::pipeline
