#include "src/cli/analyze.hpp"

#include "io/usage_error.hpp"
#include "src/cli/analyze_edit.hpp"
#include "src/cli/input_options.hpp"
#include "src/cli/interrupt.hpp"
#include "src/cli/progress.hpp"
#include "src/cli/stat_list.hpp"
#include "src/cli/unit_tables.hpp"
#include "src/pipeline/channel_fit.hpp"
#include "src/workflow/memory.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <optional>
#include <ostream>

namespace allanlot::cli {
namespace {

// The closing lines: the stage times under --verbose, then what was done and where it is.
void print_closing(const AnalyzeOptions& opt, const workflow::AnalyzeOutcome& run,
                   std::ostream& out, std::ostream& err) {
  const workflow::StageTimes& t = run.times;
  if (opt.verbose)
    err << "allanlot: stage seconds: read " << t.read << ", kernels " << t.kernels << ", psd "
        << t.psd << ", fit " << t.fit << ", write " << t.write << ", analysis wall "
        << t.analysis_wall << " (" << run.threads
        << " threads; kernels, psd and fit summed over channels); peak memory "
        << workflow::peak_rss_bytes() / (1 << 20) << " MiB (budget " << run.memory_limit / (1 << 20)
        << " MiB)\n";
  if (opt.quiet) return;
  out << "analysed " << run.n_ok - run.n_current << " of " << run.n_inputs << " input(s)";
  if (run.n_current) out << ", " << run.n_current << " already up to date (--force redoes them)";
  out << "; results in " << opt.outdir.string() << "\n";
  if (opt.summary)
    out << "lot summary: " << (opt.outdir / "lot_summary.csv").string() << " and "
        << (opt.outdir / "lot_summary.h5").string() << "\n";
}

}  // namespace

int run_analyze(const AnalyzeOptions& opt, std::ostream& out, std::ostream& err) {
  const InterruptGuard interrupts;
  std::optional<Progress> progress;
  workflow::AnalyzeHooks hooks;
  hooks.stop = stop_signal;
  hooks.started = [&](std::size_t n_files) {
    progress.emplace(opt.progress && !opt.quiet, n_files, err);
  };
  hooks.begin = [&] { progress->clear(); };
  hooks.done = [&](std::size_t n_done, std::uint64_t samples) {
    progress->update(n_done, samples);
  };
  hooks.written = [&](const io::RecordingResult& rec, std::size_t n_files) {
    if (!opt.quiet && (opt.table || n_files <= 10)) out << unit_tables(rec, opt.si);
  };
  workflow::AnalyzeOutcome run;
  try {
    run = workflow::analyze(opt, hooks, out, err);
  } catch (const io::UsageError& e) {
    throw CLI::ValidationError(e.what());  // a usage error of the command line
  }
  if (!run.ran) return run.status;
  print_closing(opt, run, out, err);
  if (run.stop_signal)
    err << "allanlot: stopped by " << signal_name(run.stop_signal) << " after " << run.n_done
        << " of " << run.n_files << " recording(s); the results written are complete"
        << (opt.summary ? " and in the lot summary" : "")
        << "; the same command finishes the lot\n";
  return run.status;
}

namespace {

// The options of analyze as given, before they are checked and turned into AnalyzeOptions.
struct AnalyzeArgs {
  AnalyzeOptions opt;
  std::string stats_text = default_stats(), taus_text = kernels::to_string(opt.grid);
  std::string gaps_text = kernels::to_string(opt.gaps);
  std::string outdir, spec_text, memory_text;
  std::vector<std::string> manifests;
  InputArgs input;
  std::vector<std::string> channels, exclude_channels;
  bool no_fit = false, no_psd = false, no_summary = false, no_progress = false;
  EditArgs edit;  // --drift, --outliers, --exclude, --dynamic
};

// Throws CLI::ValidationError (a usage error) naming the option that is wrong.
AnalyzeOptions checked_options(const AnalyzeArgs& a, const std::string& command_line) {
  AnalyzeOptions opt = a.opt;
  opt.stats = parse_stats(a.stats_text);
  try {
    opt.grid = kernels::parse_tau_grid(a.taus_text);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--taus", e.what());
  }
  opt.outdir = a.outdir;
  opt.fit = !a.no_fit;
  try {
    pipeline::parse_lowpass_choice(opt.lowpass);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--lowpass", e.what());
  }
  try {
    opt.gaps = kernels::parse_gap_policy(a.gaps_text);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--gaps", e.what());
  }
  opt.psd = !a.no_psd;
  opt.edit = checked_edit_options(a.edit);
  opt.command_line = command_line;
  opt.summary = !a.no_summary;
  opt.progress = !a.no_progress;
  opt.spec_path = a.spec_text;
  for (const std::string& m : a.manifests)
    opt.inputs.push_back("@" + m);
  if (opt.inputs.empty())
    throw CLI::ValidationError("INPUT", "no input: give files, @MANIFEST or --manifest");
  opt.input = input_options(a.input);
  opt.channels = channel_selection(a.channels, a.exclude_channels);
  if (!a.memory_text.empty()) {
    try {
      opt.memory_limit = workflow::parse_memory_size(a.memory_text);
      opt.input.memory_limit = opt.memory_limit;  // a text recording's samples too
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--memory-limit", e.what());
    }
  }
  return opt;
}

}  // namespace

Command add_analyze_command(CLI::App& app) {
  auto a = std::make_shared<AnalyzeArgs>();
  auto* sub = app.add_subcommand("analyze", "Analyse recordings: Allan-family deviations, "
                                            "results per input and a lot summary");
  sub->add_option("-o,--output", a->outdir, "Output directory")->required();
  sub->add_option("inputs", a->opt.inputs,
                  "Recordings (HDF5, text: .txt .dat .csv .tsv, optionally .gz), directories, "
                  "or @MANIFEST");
  sub->add_option("--manifest", a->manifests, "A file listing recordings, one per line");
  add_input_options(sub, a->input);
  sub->add_option("--stats", a->stats_text, "Comma-separated statistics, or all")
      ->capture_default_str();
  sub->add_option("--taus", a->taus_text,
                  "Tau grid: octave, decade, all, stable32 (Stable32's all-tau list: every m "
                  "up to K = floor(215 / floor(log10(N - 1))), then steps of floor(m / K) + 1; "
                  "MTIE 2^k - 1; Theo1 twice the list from 5), stable32:K, log:K (K per decade) "
                  "or m:LIST")
      ->capture_default_str();
  sub->add_option("--confidence", a->opt.confidence,
                  "Confidence level of the intervals dev_lo, dev_hi")
      ->check(finite_number() & CLI::Range(0.001, 0.999))
      ->capture_default_str();
  add_channel_options(sub, a->channels, a->exclude_channels);
  sub->add_option("--threads", a->opt.threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  sub->add_flag("--no-fit", a->no_fit, "Do not fit equation (3) (no fit/ group)");
  sub->add_option("--lowpass", a->opt.lowpass,
                  "The sensor's filter in the eq. (3) fit: auto (named from the curve; the "
                  "taus it biases are left out when that lowers chi2/dof), none (every tau), "
                  "cutoff_hz=X (first order) or taps=X (moving average)")
      ->capture_default_str();
  sub->add_option("--model-poor-fits", a->opt.model_poor_fits,
                  "A channel whose eq. (3) fit is poor: auto (modelled as diagnose does, eq. (3) "
                  "plus the effects the data name; its terms reported), off (eq. (3) alone)")
      ->check(CLI::IsMember({"auto", "off"}))
      ->capture_default_str();
  // The noise model (docs/clocks.md "The power-law model").
  sub->add_option("--model", a->opt.noise_model,
                  "The noise model: auto (power-law levels h_alpha for clock channels, eq. (3) "
                  "for IMU channels), eq3 or powerlaw for every channel")
      ->check(CLI::IsMember({"auto", "eq3", "powerlaw"}))
      ->capture_default_str();
  sub->add_option("--gaps", a->gaps_text,
                  "What missing samples (NaN) become: fill:N (runs of at most N samples "
                  "interpolated, longer runs left as gaps), fill (every run), skip (every term "
                  "touching a gap left out)")
      ->capture_default_str();
  add_edit_options(sub, a->edit);
  sub->add_flag("--no-psd", a->no_psd, "Do not compute the PSD and the eq. (2) cross-check");
  sub->add_flag("--table", a->opt.table,
                "Print each unit's coefficient table (default: when at most 10 inputs)");
  sub->add_flag("--si", a->opt.si,
                "The coefficient table in SI units (rad/s, m/s^2 and seconds, as robotics tools "
                "take them) instead of datasheet units");
  sub->add_flag("-v,--verbose", a->opt.verbose, "Print per-stage timings");
  sub->add_flag("-q,--quiet", a->opt.quiet, "Print only errors");
  sub->add_flag("--force", a->opt.force,
                "Redo recordings whose results in OUTDIR are complete and current (by "
                "default they are skipped)");
  sub->add_flag("--no-summary", a->no_summary,
                "Do not write the lot summary (a Slurm task; the merge job runs summarize)");
  sub->add_option("--spec", a->spec_text,
                  "Spec file (JSON): pass/fail limits per channel and term for the summary");
  sub->add_option("--memory-limit", a->memory_text,
                  "Memory for the channels in flight, e.g. 8G, 512M or 40% (default 50%)");
  sub->add_flag("--no-progress", a->no_progress, "No progress line on stderr");
  return {sub, [a](const std::string& command_line) {
            return run_analyze(checked_options(*a, command_line), std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
