// `allanlot analyze` (docs/cli.md "Command: analyze"): the batch driver over recordings. Each
// channel is analysed by src/pipeline/channel.hpp; the driver expands the inputs, skips the
// recordings whose results are current (resume), reads channels in memory-bounded waves across
// threads, writes one results file per recording and the lot summary (src/lot/summary.hpp).
#pragma once

#include "io/input_options.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "src/cli/cli.hpp"
#include "src/cli/inputs.hpp"
#include "src/pipeline/channel_edits.hpp"

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

struct AnalyzeOptions {
  std::vector<std::string> inputs;   // files, directories, manifests
  std::filesystem::path outdir;      // results and lot summary go here
  std::vector<kernels::Stat> stats;  // statistics to compute, in output order
  kernels::TauGridSpec grid;         // which taus
  ChannelSelection channels;         // --channels, --exclude-channels (all by default)
  int threads = 0;                   // 0 = OMP_NUM_THREADS, else all cores
  double confidence = 0.683;         // confidence level of dev_lo / dev_hi, in (0, 1)
  bool fit = true;                   // write fit/ (the eq. (3) fit); --no-fit turns it off
  // --lowpass: the sensor's filter in the fit (auto, none, cutoff_hz=X, taps=X)
  std::string lowpass = "auto";
  // --model-poor-fits: auto models a poor eq. (3) fit as diagnose does (docs/fit-and-psd.md),
  // off keeps eq. (3) alone
  std::string model_poor_fits = "auto";
  // --model: the noise model, auto (power-law levels for clocks, eq. (3) for IMU channels),
  // eq3 or powerlaw for every channel (docs/clocks.md)
  std::string noise_model = "auto";
  kernels::GapPolicy gaps;  // --gaps: what missing samples become (default fill:10)
  bool psd = true;       // write psd/ and crosscheck/ (Welch PSD, eq. (2)); --no-psd turns it off
  bool table = false;    // print each unit's fit table (always for <= 10 inputs)
  bool si = false;       // that table in SI units (rad/s, m/s^2 and seconds)
  bool verbose = false;  // per-stage timings on stderr
  bool quiet = false;    // only errors on stderr, nothing on stdout
  std::string command_line;  // recorded in every results file
  bool force = false;        // --force: redo recordings whose results are present and current
  bool summary = true;       // --no-summary: leave the lot summary to `summarize` (Slurm tasks)
  std::filesystem::path spec_path;  // --spec: pass/fail limits for the lot summary
  // --memory-limit: bytes the channels in flight may hold (0 = half the machine's RAM). The
  // channels of a recording are read and analysed in waves that fit in it.
  std::uint64_t memory_limit = 0;
  bool progress = true;    // a progress line on stderr (off with --quiet)
  io::InputOptions input;  // --data-type and the options of text recordings
  // --drift, --outliers, --exclude, --dynamic (src/cli/analyze_edit.hpp); edit nothing by default
  pipeline::EditOptions edit;
};

/// Runs the analysis and returns the exit status of docs/cli.md (0, 1 or 2). Failures are named
/// on `err` with file, dataset and reason; the closing summary goes to `out`.
int run_analyze(const AnalyzeOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `analyze` subcommand to `app` (see cli.hpp, struct Command).
Command add_analyze_command(CLI::App& app);

}  // namespace allanlot::cli
