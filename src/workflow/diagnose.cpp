#include "src/workflow/diagnose.hpp"

#include "io/atomic_file.hpp"
#include "io/paths.hpp"
#include "io/recording.hpp"
#include "src/workflow/diagnosis_json.hpp"
#include "src/workflow/status.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

namespace allanlot::workflow {
namespace {

// The recording's channel the request names: its path or last name, or the only one.
const io::ChannelInfo& find_channel(const io::RecordingInfo& info, const DiagnoseRequest& r) {
  const io::ChannelInfo* ch = nullptr;
  std::string names;
  for (const auto& c : info.channels) {
    names += (names.empty() ? "" : ", ") + c.path;
    const std::string name = c.path.substr(c.path.find_last_of('/') + 1);
    if (r.channel.empty() ? info.channels.size() == 1 : (c.path == r.channel || name == r.channel))
      ch = &c;
  }
  if (!ch)
    throw UsageError(r.input + ": " +
                     (r.channel.empty()
                          ? "several channels (" + names + "); choose one with --channel"
                          : "no channel '" + r.channel +
                                "' (channels: " + (names.empty() ? "none" : names) + ")"));
  return *ch;
}

// The model's channel of the recording's channel `name`: the only one of a single-channel model
// file, else the one of that name.
std::size_t model_channel_of(const model::UnitModel& m, const std::string& name,
                             const std::string& model_path) {
  std::size_t mc = 0;
  if (m.single_channel) return mc;
  while (mc < m.channels.size() && m.channels[mc].name != name)
    ++mc;
  if (mc == m.channels.size())
    throw UsageError(model_path + ": no channel '" + name + "' in the unit model");
  return mc;
}

}  // namespace

ChannelDiagnosis diagnose_channel(std::span<const double> rate, double rate_hz,
                                  const model::UnitModel& given, std::size_t model_channel,
                                  const std::string& channel, const DiagnoseSettings& settings) {
  kernels::DiagnoseOptions kopt;
  kopt.mc_replicas = settings.replicas;
  kopt.max_effects = settings.max_effects;
  kopt.mc_seed = settings.seed;
  kopt.nthreads = settings.threads;
  ChannelDiagnosis out;
  out.channel = channel;
  out.model_channel = model_channel;
  out.diagnosis = kernels::diagnose(rate, rate_hz, model::to_spec(given, model_channel), kopt);
  out.given = given;
  out.corrected = given;
  model::Channel& cc = out.corrected.channels[model_channel];
  const auto& after = out.diagnosis.model_after;
  cc.terms = after.terms;
  kernels::assign_effects(cc, after);
  return out;
}

ChannelDiagnosis diagnose_recording(const DiagnoseRequest& r,
                                    const std::function<void(const std::string&)>& note) {
  // The corrected model and -o never replace the recording or the model read (an existing
  // -o results file is edited on purpose, in a copy: io::write_diagnosis).
  const std::vector<std::filesystem::path> outputs = {r.model_out, r.output};
  const std::vector<std::filesystem::path> read = {r.input, r.model_path};
  if (const std::string clash = io::outputs_conflict(outputs, read); !clash.empty())
    throw UsageError(clash);
  model::UnitModel model;
  try {
    model = model::load_model(r.model_path);
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  const io::RecordingReader reader(r.input, r.input_options);
  const io::ChannelInfo& ch = find_channel(reader.info(), r);
  const std::size_t mc =
      model_channel_of(model, ch.path.substr(ch.path.find_last_of('/') + 1), r.model_path);
  if (!ch.units.empty() && ch.units != model.channels[mc].units)
    throw UsageError(r.input + ":" + ch.path + ": units '" + ch.units +
                     "' differ from the model's '" + model.channels[mc].units + "' (" +
                     r.model_path + ")");
  kernels::LargeVector<double> y = reader.read(ch);
  if (ch.data_type == kernels::DataType::Phase) phase_to_rate(y, ch.sample_rate_hz);
  if (std::abs(model.sample_rate_hz / ch.sample_rate_hz - 1.0) > 1e-9) {
    std::ostringstream s;
    s << "the model's sample_rate_hz " << model.sample_rate_hz << " differs from the recording's "
      << ch.sample_rate_hz << "; the recording's rate is used";
    note(s.str());
  }
  return diagnose_channel(y, ch.sample_rate_hz, model, mc, ch.path, r.settings);
}

void write_diagnosis_outputs(const DiagnoseRequest& r, const ChannelDiagnosis& d) {
  if (!r.model_out.empty()) {
    model::validate(d.corrected, r.model_out);
    io::write_text_atomic(r.model_out, model::to_json(d.corrected) + "\n");
  }
  if (!r.output.empty())
    io::write_diagnosis(r.output, r.input,
                        diagnosis_record(d, std::filesystem::absolute(r.input).string()));
}

io::DiagnosisRecord diagnosis_record(const ChannelDiagnosis& cd, const std::string& source_file) {
  const kernels::Diagnosis& d = cd.diagnosis;
  io::DiagnosisRecord r;
  r.channel = cd.channel;
  r.m = d.m;
  r.tau = d.tau_s;
  r.avar_measured = d.avar_measured;
  r.edf = d.edf;
  r.avar_model_before = d.before.avar_model;
  r.avar_model_after = d.after.avar_model;
  const auto band = [&](const std::vector<double>& v) {
    return v.empty() ? std::vector<double>(d.tau_s.size(), std::nan("")) : v;
  };
  r.mc_before_lo = band(d.mc_before.avar_lo);
  r.mc_before_hi = band(d.mc_before.avar_hi);
  r.mc_after_lo = band(d.mc_after.avar_lo);
  r.mc_after_hi = band(d.mc_after.avar_hi);
  r.z_before = d.before.z;
  r.z_after = d.after.z;
  r.significant_before = d.before.significant;
  r.significant_after = d.after.significant;
  for (const auto& it : d.iterations) {
    r.effect.emplace_back(kernels::effect_name(it.effect));
    r.parameters_json.push_back(parameters_json(it.parameters).dump());
    r.gap_before.push_back(it.gap_before);
    r.gap_after.push_back(it.gap_after);
    r.delta_ic.push_back(it.delta_ic);
  }
  r.number_attributes = {{"gap_before", d.before.gap},
                         {"gap_after", d.after.gap},
                         {"gap_noise_p95", d.mc_after.gap_p95},
                         {"gap_within_noise", d.gap_within_noise ? 1.0 : 0.0},
                         {"n_eff", d.n_eff},
                         {"z_threshold", d.z_threshold},
                         {"mc_replicas", static_cast<double>(d.mc_after.replicas)}};
  r.string_attributes = {{"mc_band", "per-tau 5 % and 95 % quantiles of the replicas' avar"},
                         {"model_before", model::to_json(cd.given)},
                         {"model_after", model::to_json(cd.corrected)},
                         {"source_file", source_file},
                         {"report", diagnosis_json(cd.channel, d).dump()}};
  return r;
}

}  // namespace allanlot::workflow
