#include "src/cli/simulate.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/recording.hpp"
#include "kernels/simulate/simulate.hpp"
#include "src/cli/interrupt.hpp"
#include "src/lot/model.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <ostream>
#include <vector>

namespace fs = std::filesystem;

namespace allanlot::cli {
namespace {

// Writes one unit's recording: channel by channel through one reused buffer and plan, so a
// six-channel 90-minute unit needs one channel's samples in memory, not six.
void write_unit(const fs::path& path, const std::string& device_id, const model::UnitModel& unit,
                int unit_index, std::uint64_t seed, kernels::SimulationPlan& plan,
                std::vector<double>& buffer, int threads) {
  io::RecordingWriter writer(path.string(), device_id, unit.sample_rate_hz);
  std::vector<double> phase;
  for (std::size_t c = 0; c < unit.channels.size(); ++c) {
    plan.run(model::to_spec(unit, c), seed, model::channel_stream(unit_index, c), buffer, threads);
    const model::Channel& ch = unit.channels[c];
    if (!ch.phase_output) {
      writer.add_channel({ch.name, ch.units, buffer});
      continue;
    }
    // "output": "phase" (docs/clocks.md "Simulating clocks"): the time error x_k = tau0 sum_{j<k}
    // y_j, n + 1 points from x_0 = 0, summed in long double; a fractional frequency's phase is
    // in s.
    phase.assign(buffer.size() + 1, 0.0);
    long double x = 0;
    for (std::size_t k = 0; k < buffer.size(); ++k) {
      x += static_cast<long double>(buffer[k]) / unit.sample_rate_hz;
      phase[k + 1] = static_cast<double>(x);
    }
    io::ChannelAttributes attributes;
    attributes.data_type = "phase";
    writer.add_channel({ch.name, ch.units == "1" ? "s" : ch.units, phase}, attributes);
  }
  // The exact model each unit was drawn with, so tests and users can compare fits with truth.
  writer.add_root_attribute("simulated_model", model::to_json(unit));
  writer.add_root_attribute("simulated_seed", std::to_string(seed));
  writer.commit();
}

}  // namespace

int run_simulate(const SimulateOptions& opt, std::ostream& out, std::ostream& err) {
  model::UnitModel m;
  try {
    m = opt.model_path.empty() ? model::default_demo_model()
                               : model::load_model(opt.model_path, opt.channel);
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return 2;
  }
  const double n_real = opt.duration_s * m.sample_rate_hz;
  if (!(std::isfinite(opt.duration_s) && opt.duration_s > 0.0) || !(n_real >= 2.0) ||
      n_real > 4.0e9) {
    err << "allanlot: error: --duration " << opt.duration_s << " s at " << m.sample_rate_hz
        << " Hz gives " << n_real << " samples; need 2 to 4e9\n";
    return 2;
  }
  const auto n = static_cast<std::size_t>(std::llround(n_real));
  try {
    kernels::SimulationPlan plan(n);
    std::vector<double> buffer(n);
    if (opt.lot <= 0) {
      if (opt.output.has_parent_path()) fs::create_directories(opt.output.parent_path());
      write_unit(opt.output, opt.output.stem().string(), m, 0, opt.seed, plan, buffer, opt.threads);
      if (!opt.quiet)
        out << "wrote " << opt.output.string() << " (" << m.channels.size() << " channel(s), " << n
            << " samples each)\n";
      return 0;
    }
    std::error_code ec;
    if (fs::exists(opt.output, ec) && !fs::is_directory(opt.output, ec)) {
      err << "allanlot: error: " << opt.output.string() << " exists and is not a directory\n";
      return 2;
    }
    fs::create_directories(opt.output);
    std::string manifest = "# allanlot simulate --lot " + std::to_string(opt.lot) + " --seed " +
                           std::to_string(opt.seed) + "\n";
    // A signal stops the lot after the unit in flight (complete, never a temporary left).
    const InterruptGuard interrupts;
    for (int u = 1; u <= opt.lot; ++u) {
      if (const int sig = stop_signal()) {
        err << "allanlot: stopped by " << signal_name(sig) << " after " << u - 1 << " of "
            << opt.lot << " units; the units written are complete\n";
        return 128 + sig;
      }
      char name[32];
      std::snprintf(name, sizeof name, "unit_%04d", u);
      const model::UnitModel unit = model::draw_unit(m, opt.seed, u);
      write_unit(opt.output / (std::string(name) + ".h5"), name, unit, u, opt.seed, plan, buffer,
                 opt.threads);
      manifest += std::string(name) + ".h5\n";
    }
    io::write_text_atomic(opt.output / "manifest.txt", manifest);
    io::write_text_atomic(opt.output / "lot_model.json", model::to_json(m) + "\n");
    if (!opt.quiet)
      out << "wrote " << opt.lot << " units of " << m.channels.size() << " channel(s), " << n
          << " samples each, to " << opt.output.string() << " (manifest "
          << (opt.output / "manifest.txt").string() << ")\n";
    return 0;
  } catch (const std::bad_alloc&) {
    err << "allanlot: error: not enough memory for " << n << " samples per channel\n";
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
  }
  return 2;
}

Command add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  auto output = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "simulate", "Write simulated recordings from a noise model (default: the paper's unit)");
  sub->add_option("-o,--output", *output, "Output FILE.h5, or DIR with --lot")->required();
  sub->add_option("--model", opt->model_path, "Model file (JSON, see docs/formats.md)");
  sub->add_option("--duration", opt->duration_s, "Record length in seconds")->capture_default_str();
  sub->add_option("--seed", opt->seed, "Random seed")->check(seed_number())->capture_default_str();
  sub->add_option("--channel", opt->channel, "Dataset name of a single-channel model")
      ->capture_default_str();
  sub->add_option("--lot", opt->lot, "Write N units into the directory -o")
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--threads", opt->threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  sub->add_flag("-q,--quiet", opt->quiet, "Print only errors");
  return {sub, [opt, output](const std::string&) {
            opt->output = *output;
            return run_simulate(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
