#include "src/pipeline/channel_powerlaw.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/powerlaw/fit.hpp"
#include "kernels/powerlaw/names.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "src/pipeline/channel_fit.hpp"

#include <cstdio>
#include <stdexcept>
#include <vector>

namespace allanlot::pipeline {

namespace pl = kernels::powerlaw;

NoiseModel parse_noise_model(std::string_view text) {
  if (text == "auto") return NoiseModel::Auto;
  if (text == "eq3") return NoiseModel::Eq3;
  if (text == "powerlaw") return NoiseModel::PowerLaw;
  throw std::invalid_argument("unknown noise model '" + std::string(text) +
                              "' (auto, eq3 or powerlaw)");
}

bool uses_powerlaw(NoiseModel choice, const io::ChannelResult& channel) {
  if (choice == NoiseModel::Auto) return pl::is_clock_channel(channel.units, channel.data_type);
  return choice == NoiseModel::PowerLaw;
}

io::PowerLawRecord powerlaw_channel(const io::ChannelResult& result,
                                    const kernels::PhaseData& phase,
                                    const kernels::StatResult& oadev, double confidence,
                                    int threads) {
  const kernels::StatResult* mdev = nullptr;
  for (const auto& [name, s] : result.stats)
    if (name == kernels::stat_name(kernels::Stat::Mdev)) mdev = &s;
  // MDEV tells white from flicker PM (kernels/powerlaw/fit.hpp): computed at OADEV's m when
  // --stats left it out (not written: allan/ holds what was asked for).
  kernels::StatResult own;
  if (mdev == nullptr && (!phase.has_gaps() || kernels::supports_gaps(kernels::Stat::Mdev))) {
    own = kernels::compute(kernels::Stat::Mdev, phase, oadev.m, threads);
    kernels::add_confidence(kernels::Stat::Mdev, phase, own, confidence, threads);
    mdev = &own;
  }
  pl::Options options;
  options.threads = threads;
  const pl::Result r = pl::fit(oadev, mdev, phase.tau0_s, options);
  io::PowerLawRecord rec;
  rec.method = "h_alpha (alpha 2..-2) by NNLS on OAVAR and MVAR (SP1065 sec. 5.2.4-5.2.5), "
               "weights edf/(2 model^2) reweighted; sigma: sandwich with the model covariance";
  rec.status = std::string(pl::status_name(r.status));
  for (const pl::Level& l : r.levels)
    rec.levels.push_back({l.alpha, std::string(pl::noise_type_name(l.alpha)), l.h, l.h_sigma,
                          l.h_upper, l.detected});
  rec.tau = r.tau_s;
  rec.adev_model = r.adev_model;
  rec.mdev_tau = r.mdev_tau_s;
  rec.mdev_model = r.mdev_model;
  return rec;
}

std::string powerlaw_table(const std::string& device_id, const io::ChannelResult& ch) {
  if (!ch.powerlaw) return "";
  const io::PowerLawRecord& p = *ch.powerlaw;
  std::string out = device_id + ": " + ch.path + " power-law noise levels, S_y(f) = h_alpha " +
                    "f^alpha (" + p.status + ")\n";
  if (p.status != "ok") return out;
  std::vector<std::vector<std::string>> rows = {{"noise type", "alpha", "h_alpha", "unit"}};
  for (const io::PowerLawLevelRecord& l : p.levels) {
    char v[64], unit[32];
    if (l.detected)
      std::snprintf(v, sizeof v, "%.3e +- %.2e", l.h, l.h_sigma);
    else
      std::snprintf(v, sizeof v, "< %.2e (not detected)", l.h_upper);
    std::snprintf(unit, sizeof unit, "Hz^%d", static_cast<int>(-1 - l.alpha));
    rows.push_back({l.name, std::to_string(l.alpha), v, unit});
  }
  return out + aligned_rows(rows);
}

}  // namespace allanlot::pipeline
