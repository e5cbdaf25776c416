#include "src/cli/cli.hpp"

#include "src/cli/analyze.hpp"
#include "src/cli/diagnose.hpp"
#include "src/cli/export.hpp"
#include "src/cli/simulate.hpp"
#include "src/report/report.hpp"

#include <allanlot/version.hpp>

#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>
#include <vector>

namespace allanlot::cli {
namespace {

std::string join_args(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    if (i) s += ' ';
    const std::string a = argv[i];
    s += a.find_first_of(" \t'\"") == std::string::npos ? a : "'" + a + "'";
  }
  return s;
}

// Validators shared by the commands.
const auto kThreads = CLI::Range(0, 4096);

std::vector<kernels::Stat> parse_stats(const std::string& list) {
  std::vector<kernels::Stat> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto s = kernels::parse_stat(name);
    if (!s) {
      std::string known;
      for (const auto k : kernels::all_stats())
        known += (known.empty() ? "" : ", ") + std::string(kernels::stat_name(k));
      throw CLI::ValidationError("--stats",
                                 "unknown statistic '" + name + "' (known: " + known + ")");
    }
    bool dup = false;
    for (const auto k : out)
      dup = dup || k == *s;
    if (!dup) out.push_back(*s);
  }
  if (out.empty()) throw CLI::ValidationError("--stats", "empty list");
  return out;
}

// The default statistics of docs/cli.md, reduced to those this build computes (so that the default
// never names a statistic that is not there).
std::string default_stats() {
  std::string s;
  for (const char* name : {"oadev", "mdev", "hdev", "ohdev", "tdev", "totdev"}) {
    if (!kernels::parse_stat(name)) continue;
    s += (s.empty() ? "" : ",") + std::string(name);
  }
  return s;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"allanlot: Allan-family noise characterization of sensor production lots"};
  app.set_version_flag("--version", std::string("allanlot ") + kVersion + " (" + kGitSha + ")");
  app.require_subcommand(1);

  AnalyzeOptions aopt;
  std::string stats_text = default_stats(), taus_text = kernels::to_string(aopt.grid);
  std::string outdir;
  auto* analyze = app.add_subcommand("analyze", "Analyse recordings: Allan-family deviations, "
                                                "results per input and a lot summary");
  analyze->add_option("-o,--output", outdir, "Output directory")->required();
  analyze->add_option("inputs", aopt.inputs, "HDF5 files, directories, or *.txt manifests")
      ->required();
  analyze->add_option("--stats", stats_text, "Comma-separated statistics")->capture_default_str();
  analyze->add_option("--taus", taus_text, "Tau grid: octave, decade, all, log:K or m:LIST")
      ->capture_default_str();
  analyze
      ->add_option("--confidence", aopt.confidence,
                   "Confidence level of the intervals dev_lo, dev_hi")
      ->check(CLI::Range(0.001, 0.999))
      ->capture_default_str();
  analyze->add_option("--channels", aopt.channels_glob,
                      "Only channels whose path or name matches this glob");
  analyze
      ->add_option("--threads", aopt.threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(kThreads);
  bool no_fit = false;
  analyze->add_flag("--no-fit", no_fit, "Do not fit equation (3) (no fit/ group)");
  bool no_psd = false;
  analyze->add_flag("--no-psd", no_psd, "Do not compute the PSD and the eq. (2) cross-check");
  analyze->add_flag("--table", aopt.table,
                    "Print each unit's coefficient table (default: when at most 10 inputs)");
  analyze->add_flag("-v,--verbose", aopt.verbose, "Print per-stage timings");
  analyze->add_flag("-q,--quiet", aopt.quiet, "Print only errors");
  analyze->add_flag("--force", aopt.force,
                    "Redo recordings whose results in OUTDIR are complete and current (by "
                    "default they are skipped)");
  bool no_summary = false;
  analyze->add_flag("--no-summary", no_summary,
                    "Do not write the lot summary (a Slurm task; the merge job runs summarize)");
  std::string spec_text, memory_text;
  analyze->add_option("--spec", spec_text,
                      "Spec file (JSON): pass/fail limits per channel and term for the summary");
  analyze->add_option("--memory-limit", memory_text,
                      "Memory for the channels in flight, e.g. 8G, 512M or 40% (default 50%)");
  bool no_progress = false;
  analyze->add_flag("--no-progress", no_progress, "No progress line on stderr");

  SimulateOptions sopt;
  std::string sim_out;
  auto* simulate = app.add_subcommand(
      "simulate", "Write simulated recordings from a noise model (default: the paper's unit)");
  simulate->add_option("-o,--output", sim_out, "Output FILE.h5, or DIR with --lot")->required();
  simulate->add_option("--model", sopt.model_path, "Model file (JSON, see docs/formats.md)");
  simulate->add_option("--duration", sopt.duration_s, "Record length in seconds")
      ->capture_default_str();
  simulate->add_option("--seed", sopt.seed, "Random seed")->capture_default_str();
  simulate->add_option("--channel", sopt.channel, "Dataset name of a single-channel model")
      ->capture_default_str();
  simulate->add_option("--lot", sopt.lot, "Write N units into the directory -o")
      ->check(CLI::Range(1, 1000000));
  simulate
      ->add_option("--threads", sopt.threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(kThreads);
  simulate->add_flag("-q,--quiet", sopt.quiet, "Print only errors");

  SummarizeOptions sumopt;
  std::string sum_dir, sum_spec, sum_manifest;
  auto* summarize = app.add_subcommand(
      "summarize", "Rebuild lot_summary.h5 and lot_summary.csv from the results files present");
  summarize->add_option("outdir", sum_dir, "Output directory of analyze")->required();
  summarize->add_option("--spec", sum_spec,
                        "Spec file (JSON): pass/fail limits per channel and term");
  summarize->add_option(
      "--manifest", sum_manifest,
      "Manifest of the lot: recordings without a results file are listed as failed");
  summarize->add_flag("-q,--quiet", sumopt.quiet, "Print only errors");

  // Commands that live in their own files, one line each.
  std::vector<Command> commands;
  commands.push_back(add_diagnose_command(app));
  commands.push_back(add_report_command(app));
  commands.push_back(add_export_command(app));

  try {
    app.parse(argc, argv);
    for (const auto& c : commands)
      if (*c.app) return c.run();
    if (*analyze) {
      aopt.stats = parse_stats(stats_text);
      try {
        aopt.grid = kernels::parse_tau_grid(taus_text);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--taus", e.what());
      }
      aopt.outdir = outdir;
      aopt.fit = !no_fit;
      aopt.psd = !no_psd;
      aopt.command_line = join_args(argc, argv);
      aopt.summary = !no_summary;
      aopt.progress = !no_progress;
      aopt.spec_path = spec_text;
      if (!memory_text.empty()) {
        try {
          aopt.memory_limit = parse_memory_size(memory_text);
        } catch (const std::invalid_argument& e) {
          throw CLI::ValidationError("--memory-limit", e.what());
        }
      }
      return run_analyze(aopt, std::cout, std::cerr);
    }
    if (*simulate) {
      sopt.output = sim_out;
      return run_simulate(sopt, std::cout, std::cerr);
    }
    if (*summarize) {
      sumopt.outdir = sum_dir;
      sumopt.spec_path = sum_spec;
      sumopt.manifest = sum_manifest;
      return run_summarize(sumopt, std::cout, std::cerr);
    }
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kExitOk;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // CLI11's own exit codes differ per error; docs/cli.md says 2 for every usage error.
    std::cerr << "allanlot: usage error: " << e.what() << "\n"
              << "Run 'allanlot --help' or 'allanlot <command> --help'.\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  return kExitUsage;
}

}  // namespace allanlot::cli
