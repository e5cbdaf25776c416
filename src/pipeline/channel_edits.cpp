#include "src/pipeline/channel_edits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace allanlot::pipeline {
namespace {

void add_note(io::ChannelResult& r, const std::string& note) {
  r.notes += (r.notes.empty() ? "" : "; ") + note;
}

// Most points of drift/'s residual plot: enough for a page-wide curve, small in the file.
constexpr std::size_t kResidualBlocks = 512;

// The residuals' block means at their blocks' centres (NaN samples left out; an empty block
// is left out).
void residual_blocks(io::DriftRecord& d, std::span<const double> samples, double tau0,
                     const kernels::DriftFit& fit) {
  const std::vector<double> res = kernels::drift_residuals(samples, tau0, fit);
  const std::size_t n = res.size(), blocks = std::min(n, kResidualBlocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t lo = b * n / blocks, hi = (b + 1) * n / blocks;
    long double sum = 0;
    std::size_t used = 0;
    for (std::size_t i = lo; i < hi; ++i)
      if (!std::isnan(res[i])) sum += res[i], ++used;
    if (used == 0) continue;
    d.t.push_back((static_cast<double>(lo + hi - 1) / 2) * tau0);
    d.residual.push_back(static_cast<double>(sum / static_cast<long double>(used)));
  }
}

// Each parameter's unit. Rate data: u the channel's units ("1" when none). Phase data: the
// channel's units are the phase's (a clock's "s"), its frequency is that per second ("1" for s).
std::vector<std::string> parameter_units(kernels::DriftModel m, const std::string& units) {
  if (m == kernels::DriftModel::Quadratic) {
    const std::string phase = units.empty() ? "s" : units;
    const std::string freq = phase == "s" ? "1" : phase + "/s";
    return {phase, freq, freq + "/s"};
  }
  const std::string u = units.empty() ? "1" : units;
  switch (m) {
  case kernels::DriftModel::Linear:
    return {u, u + "/s"};
  case kernels::DriftModel::Log:
    return {u, "1/s", u};
  case kernels::DriftModel::Diffusion:
    return {u, u + "/s^0.5", "s"};
  default:
    break;
  }
  return {};
}

io::DriftRecord drift_record(const kernels::DriftFit& fit, std::span<const double> samples,
                             double tau0, const std::string& units) {
  io::DriftRecord d;
  d.model = std::string(kernels::to_string(fit.model));
  d.fitted_to = fit.fitted_to == kernels::DataType::Rate ? "frequency" : "phase";
  d.parameter = fit.names;
  d.value = fit.value;
  d.sigma = fit.sigma;
  d.unit = parameter_units(fit.model, units);
  d.noise_white_pm = fit.noise.white_pm;
  d.noise_white_fm = fit.noise.white_fm;
  d.noise_rw_fm = fit.noise.rw_fm;
  d.n_used = fit.n_used;
  residual_blocks(d, samples, tau0, fit);
  return d;
}

std::string edits_note(const std::vector<io::EditRecord>& edits) {
  std::int64_t outliers = 0, ranges = 0, excluded = 0;
  for (const io::EditRecord& e : edits) {
    if (e.kind == "outlier")
      ++outliers;
    else
      ++ranges, excluded += e.last - e.first + 1;
  }
  std::string note = "edits:";
  if (ranges)
    note += " " + std::to_string(excluded) + " samples excluded in " + std::to_string(ranges) +
            " ranges";
  if (ranges && outliers) note += ",";
  if (outliers) note += " " + std::to_string(outliers) + " outliers removed";
  return note + " (listed in edits/; the gap policy fills or skips them)";
}

}  // namespace

void edit_channel(io::ChannelResult& r, const io::ChannelInfo& channel,
                  kernels::LargeVector<double>& samples, const EditOptions& opt) {
  const std::span<double> s(samples.data(), samples.size());
  const double rate = channel.sample_rate_hz, tau0 = 1.0 / rate;
  std::vector<kernels::Edit> edits;
  if (!opt.exclude.empty()) {
    edits = kernels::exclusion_edits(static_cast<std::int64_t>(s.size()), rate, opt.exclude);
    kernels::apply_edits(s, edits);
  }
  if (opt.outlier_sigmas > 0) {
    // On the record with the excluded ranges gone: their samples judge nothing.
    const std::vector<kernels::Edit> out =
        kernels::find_outliers(s, channel.data_type, opt.outlier_sigmas);
    kernels::apply_edits(s, out);
    edits.insert(edits.end(), out.begin(), out.end());
  }
  for (const kernels::Edit& e : edits)
    r.edits.push_back({std::string(kernels::to_string(e.kind)), e.first, e.last,
                       static_cast<double>(e.first) * tau0, static_cast<double>(e.last) * tau0,
                       e.value, e.sigmas});
  if (!r.edits.empty()) add_note(r, edits_note(r.edits));
  if (opt.drift == kernels::DriftModel::None) return;
  const kernels::DriftModel model = kernels::drift_model_for(opt.drift, channel.data_type);
  const kernels::DriftFit fit = kernels::fit_drift(s, channel.data_type, tau0, model);
  r.drift = drift_record(fit, s, tau0, r.units);
  kernels::remove_drift(s, tau0, fit);
  std::string note = "drift (" + r.drift->model + ", removed):";
  for (std::size_t i = 0; i < fit.value.size(); ++i) {
    char text[128];
    std::snprintf(text, sizeof text, "%s %s = %.6g +- %.2g %s", i ? "," : "", fit.names[i].c_str(),
                  fit.value[i], fit.sigma[i], r.drift->unit[i].c_str());
    note += text;
  }
  add_note(r, note);
}

void dynamic_channel(io::ChannelResult& r, const io::ChannelInfo& channel,
                     std::span<const double> samples, const EditOptions& opt, int threads) {
  if (!opt.dynamic.enabled()) return;
  const double per = opt.dynamic.in_seconds ? channel.sample_rate_hz : 1.0;
  const auto window = static_cast<std::int64_t>(std::llround(opt.dynamic.window * per));
  const auto step = opt.dynamic.step > 0
                        ? static_cast<std::int64_t>(std::llround(opt.dynamic.step * per))
                        : std::max<std::int64_t>(1, window / 4);
  try {
    const kernels::DynamicAdev d =
        kernels::dynamic_oadev(samples, channel.data_type, channel.sample_rate_hz, window,
                               std::max<std::int64_t>(step, 1), threads);
    r.dynamic = io::DynamicRecord{d.window, d.step, d.m, d.tau_s, d.t_center_s, d.oadev};
  } catch (const std::invalid_argument& e) {
    add_note(r, std::string("dynamic oadev not computed: ") + e.what());
  }
}

}  // namespace allanlot::pipeline
