#include "src/cli/diagnose.hpp"

#include "io/atomic_file.hpp"
#include "io/diagnosis.hpp"
#include "io/error.hpp"
#include "io/paths.hpp"
#include "io/recording.hpp"
#include "io/usage_error.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "src/cli/diagnosis_json.hpp"
#include "src/cli/input_options.hpp"
#include "src/lot/model.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <sstream>

namespace allanlot::cli {
namespace {

// A usage-level failure (exit status 2), as opposed to a failed diagnosis (1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string bands_text(const std::vector<kernels::Band>& bands) {
  if (bands.empty()) return "none";
  std::string s;
  for (const auto& b : bands)
    s += (s.empty() ? "" : ", ") + num(b.tau_lo_s) + " s .. " + num(b.tau_hi_s) + " s (" +
         (b.sign > 0 ? "measured above" : "measured below") + ", max |z| " + num(b.max_abs_z) + ")";
  return s;
}

std::string params_text(const std::vector<kernels::Parameter>& ps) {
  std::string s;
  for (const auto& p : ps)
    s += (s.empty() ? "" : ", ") + p.name +
         (p.bound < 0   ? " < " + num(p.value) + " (at the search's lower end)"
          : p.bound > 0 ? " > " + num(p.value) + " (at the search's upper end)"
                        : " = " + num(p.value) +
                              (std::isfinite(p.sigma) ? " +- " + num(p.sigma)
                               : p.value == 0.0       ? std::string(" (at zero)")
                                                      : std::string()));
  return s;
}

void print_report(std::ostream& out, const std::string& file, const std::string& channel,
                  const std::string& model_path, const kernels::Diagnosis& d) {
  out << "diagnose " << file << ":" << channel << " against " << model_path << "\n";
  out << "  " << d.tau_s.size() << " taus from " << num(d.tau_s.front()) << " s to "
      << num(d.tau_s.back()) << " s, about " << num(d.n_eff)
      << " independent; a tau is significant beyond |z| = " << num(d.z_threshold) << "\n";
  out << "  given model: gap " << num(d.before.gap) << " (the model simulated "
      << d.mc_before.replicas << " times: median " << num(d.mc_before.gap_median) << ", 95 % "
      << num(d.mc_before.gap_p95) << ")\n";
  out << "  significant bands: " << bands_text(d.before.bands) << "\n";
  if (d.line.found)
    out << "  PSD witness: line at " << num(d.line.frequency_hz) << " Hz (peak/background "
        << num(d.line.peak_ratio) << ", threshold " << num(d.line.threshold) << ")\n";
  if (const auto& nb = d.line.narrowband; d.line.wide_hz > 0.0) {
    out << "  PSD witness: the peak at " << num(d.line.wide_hz)
        << " Hz is wider than a line (a narrowband process)";
    if (nb.found)
      out << ", as a resonance: f0 " << num(nb.frequency_hz) << " +- " << num(nb.frequency_sigma)
          << " Hz, q " << num(nb.q) << " +- " << num(nb.q_sigma) << ", sigma " << num(nb.sigma)
          << " +- " << num(nb.sigma_sigma);
    out << "\n";
  }
  if (d.step.found)
    out << "  time-domain witness: jump of " << num(d.step.size) << " at " << num(d.step.time_s)
        << " s (" << num(d.step.statistic) << " rms at " << d.step.scale_m << " samples, p "
        << num(d.step.p_value) << " < " << num(d.step.false_alarm) << ")\n";
  if (d.trend.found)
    out << "  trend witness: slope " << num(d.trend.slope) << " +- " << num(d.trend.sigma)
        << " per s (z " << num(d.trend.z) << ", p " << num(d.trend.p_value) << " < "
        << num(d.trend.false_alarm) << ")\n";
  for (std::size_t i = 0; i < d.iterations.size(); ++i) {
    const auto& it = d.iterations[i];
    out << "iteration " << i + 1 << ": add " << kernels::effect_name(it.effect) << " (criterion +"
        << num(it.delta_ic) << ")\n";
    out << "    " << params_text(it.parameters) << "\n";
    out << "    gap " << num(it.gap_before) << " -> " << num(it.gap_after) << "\n";
    out << "    bands before: " << bands_text(it.bands_before) << "\n";
    out << "    bands after:  " << bands_text(it.bands_after) << "\n";
    std::string others;
    for (const auto& c : it.candidates)
      if (c.evaluated && c.effect != it.effect)
        others += (others.empty() ? "" : ", ") + std::string(kernels::effect_name(c.effect)) + " " +
                  num(c.delta_ic);
    if (!others.empty()) out << "    other candidates (criterion): " << others << "\n";
  }
  if (d.effects_named.empty())
    out << "no effect is missing: no candidate improves the agreement significantly\n";
  out << "given coefficients (given -> re-estimated): ";
  std::string rev;
  for (const auto& r : d.revisions)
    rev += (rev.empty() ? "" : ", ") + r.name + " " + num(r.given) + " -> " + num(r.estimated) +
           (std::isfinite(r.sigma) ? " +- " + num(r.sigma) : "");
  out << (rev.empty() ? "none" : rev) << "\n";
  out << (d.coefficients_wrong
              ? "  the given coefficients are WRONG (re-estimating them is significant); the "
                "corrected model uses the re-estimated values\n"
              : "  the given coefficients are consistent with the measurement and are kept\n");
  std::string named;
  for (const auto e : d.effects_named)
    named += (named.empty() ? "" : ", ") + std::string(kernels::effect_name(e));
  out << "result: effects named: " << (named.empty() ? "none" : named) << "; gap "
      << num(d.before.gap) << " -> " << num(d.after.gap) << " ("
      << (d.gap_within_noise ? "within" : "NOT within")
      << " statistical noise: the corrected model simulated " << d.mc_after.replicas
      << " times gives 95 % " << num(d.mc_after.gap_p95) << ")\n";
  out << "  significant bands after: " << bands_text(d.after.bands) << "\n";
  for (const auto& n : d.notes)
    out << "note: " << n << "\n";
}

io::DiagnosisRecord make_record(const std::string& channel, const kernels::Diagnosis& d,
                                const Json& report, const std::string& model_before,
                                const std::string& model_after, const std::string& source) {
  io::DiagnosisRecord r;
  r.channel = channel;
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
    Json p = parameters_json(it.parameters);
    r.parameters_json.push_back(p.dump());
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
                         {"model_before", model_before},
                         {"model_after", model_after},
                         {"source_file", source},
                         {"report", report.dump()}};
  return r;
}

}  // namespace

int run_diagnose(const DiagnoseOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    // The corrected model and -o never replace the recording or the model read (an existing
    // -o results file is edited on purpose, in a copy: io::write_diagnosis).
    const std::vector<std::filesystem::path> outputs = {opt.model_out, opt.output};
    const std::vector<std::filesystem::path> read = {opt.input, opt.model_path};
    if (const std::string clash = io::outputs_conflict(outputs, read); !clash.empty())
      throw UsageError(clash);
    model::UnitModel model;
    try {
      model = model::load_model(opt.model_path);
    } catch (const std::exception& e) {
      throw UsageError(e.what());
    }
    const io::RecordingReader reader(opt.input, opt.input_options);
    const io::RecordingInfo& info = reader.info();
    const io::ChannelInfo* ch = nullptr;
    std::string names;
    for (const auto& c : info.channels) {
      names += (names.empty() ? "" : ", ") + c.path;
      const std::string name = c.path.substr(c.path.find_last_of('/') + 1);
      if (opt.channel.empty() ? info.channels.size() == 1
                              : (c.path == opt.channel || name == opt.channel))
        ch = &c;
    }
    if (!ch)
      throw UsageError(opt.input + ": " +
                       (opt.channel.empty()
                            ? "several channels (" + names + "); choose one with --channel"
                            : "no channel '" + opt.channel +
                                  "' (channels: " + (names.empty() ? "none" : names) + ")"));
    const std::string name = ch->path.substr(ch->path.find_last_of('/') + 1);
    std::size_t mc = 0;
    if (!model.single_channel) {
      while (mc < model.channels.size() && model.channels[mc].name != name)
        ++mc;
      if (mc == model.channels.size())
        throw UsageError(opt.model_path + ": no channel '" + name + "' in the unit model");
    }
    if (!ch->units.empty() && ch->units != model.channels[mc].units)
      throw UsageError(opt.input + ":" + ch->path + ": units '" + ch->units +
                       "' differ from the model's '" + model.channels[mc].units + "' (" +
                       opt.model_path + ")");
    kernels::LargeVector<double> y = reader.read(*ch);
    if (ch->data_type == kernels::DataType::Phase) {
      // Phase samples to rate: successive differences times the sample rate (a NaN point makes
      // both of its increments missing, as kernels::phase_from_phase treats it).
      for (std::size_t k = 0; k + 1 < y.size(); ++k)
        y[k] = (y[k + 1] - y[k]) * ch->sample_rate_hz;
      if (!y.empty()) y.pop_back();
    }
    if (std::abs(model.sample_rate_hz / ch->sample_rate_hz - 1.0) > 1e-9)
      err << "allanlot: note: the model's sample_rate_hz " << model.sample_rate_hz
          << " differs from the recording's " << ch->sample_rate_hz
          << "; the recording's rate is used\n";

    kernels::DiagnoseOptions kopt;
    kopt.mc_replicas = opt.replicas;
    kopt.max_effects = opt.max_effects;
    kopt.mc_seed = opt.seed;
    kopt.nthreads = opt.threads;
    const kernels::Diagnosis d =
        kernels::diagnose(y, ch->sample_rate_hz, model::to_spec(model, mc), kopt);

    model::UnitModel corrected = model;
    model::Channel& cc = corrected.channels[mc];
    cc.terms = d.model_after.terms;
    cc.sinusoids = d.model_after.sinusoids;
    cc.markovs = d.model_after.markovs;
    cc.resonances = d.model_after.resonances;
    cc.steps = d.model_after.steps;
    cc.lowpass = d.model_after.lowpass;
    const std::string before_json = model::to_json(model), after_json = model::to_json(corrected);
    const Json report = diagnosis_json(ch->path, d);
    if (opt.json)
      out << report.dump() << "\n";
    else
      print_report(out, opt.input, ch->path, opt.model_path, d);
    if (!opt.model_out.empty()) {
      model::validate(corrected, opt.model_out);
      io::write_text_atomic(opt.model_out, after_json + "\n");
    }
    if (!opt.output.empty())
      io::write_diagnosis(opt.output, opt.input,
                          make_record(ch->path, d, report, before_json, after_json,
                                      std::filesystem::absolute(opt.input).string()));
    return kExitOk;
  } catch (const UsageError& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const io::UsageError& e) {
    err << "allanlot: usage error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const io::Error& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return e.reason().find("the input is never written") != std::string::npos ? kExitUsage
                                                                              : kExitSomeFailed;
  } catch (const std::exception& e) {
    err << "allanlot: error: " << opt.input << ": " << e.what() << "\n";
    return kExitSomeFailed;
  }
}

Command add_diagnose_command(CLI::App& app) {
  auto opt = std::make_shared<DiagnoseOptions>();
  auto input = std::make_shared<InputArgs>();
  auto* sub = app.add_subcommand(
      "diagnose", "Compare a measured channel with a noise model, name the missing effects and "
                  "write the corrected model");
  sub->add_option("input", opt->input, "Recording (HDF5 or text)")->required();
  add_input_options(sub, *input);
  sub->add_option("--model", opt->model_path, "Model file (JSON, see docs/formats.md)")->required();
  sub->add_option("--channel", opt->channel, "Channel path or name (default: the only channel)");
  sub->add_option("-o,--output", opt->output,
                  "Write group /<channel>/diagnosis to this HDF5 file (new or existing)");
  sub->add_option("--model-out", opt->model_out, "Write the corrected model file (JSON)");
  sub->add_flag("--json", opt->json,
                "Print one JSON object (docs/diagnose.md) instead of the report");
  sub->add_option("--replicas", opt->replicas, "Monte Carlo replicas per model")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  sub->add_option("--max-effects", opt->max_effects, "At most this many effects are named")
      ->check(CLI::Range(1, kernels::kMaxEffects))
      ->capture_default_str();
  sub->add_option("--seed", opt->seed, "Seed of the Monte Carlo replicas")
      ->check(seed_number())
      ->capture_default_str();
  sub->add_option("--threads", opt->threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  return {sub, [opt, input](const std::string&) {
            opt->input_options = input_options(*input);
            return run_diagnose(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
