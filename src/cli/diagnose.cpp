#include "src/cli/diagnose.hpp"

#include "io/error.hpp"
#include "io/usage_error.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "src/cli/input_options.hpp"
#include "src/workflow/diagnose.hpp"
#include "src/workflow/diagnosis_json.hpp"
#include "src/workflow/status.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <ostream>

namespace allanlot::cli {
namespace {

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

}  // namespace

int run_diagnose(const DiagnoseOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    const workflow::ChannelDiagnosis d = workflow::diagnose_recording(
        opt, [&](const std::string& note) { err << "allanlot: note: " << note << "\n"; });
    if (opt.json)
      out << workflow::diagnosis_json(d.channel, d.diagnosis).dump() << "\n";
    else
      print_report(out, opt.input, d.channel, opt.model_path, d.diagnosis);
    workflow::write_diagnosis_outputs(opt, d);
    return kExitOk;
  } catch (const workflow::UsageError& e) {
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
  sub->add_option("--replicas", opt->settings.replicas, "Monte Carlo replicas per model")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  sub->add_option("--max-effects", opt->settings.max_effects, "At most this many effects are named")
      ->check(CLI::Range(1, kernels::kMaxEffects))
      ->capture_default_str();
  sub->add_option("--seed", opt->settings.seed, "Seed of the Monte Carlo replicas")
      ->check(seed_number())
      ->capture_default_str();
  sub->add_option("--threads", opt->settings.threads,
                  "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  return {sub, [opt, input](const std::string&) {
            opt->input_options = input_options(*input);
            return run_diagnose(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
