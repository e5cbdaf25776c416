// The analyze workflow (docs/cli.md "Command: analyze", docs/lots-and-slurm.md "Running a lot"):
// the batch over recordings. It expands the inputs (src/workflow/inputs.hpp), skips the
// recordings whose results are current (src/workflow/resume.hpp), analyses each of the others
// (src/workflow/analyze_recording.hpp), writes one results file per recording and the lot
// summary (src/lot/summary.hpp), and says what it did. The command line adds its options, the
// progress line, the coefficient tables, the closing lines and the signals.
#pragma once

#include "io/input_options.hpp"
#include "io/results.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "src/pipeline/channel_edits.hpp"
#include "src/workflow/inputs.hpp"
#include "src/workflow/status.hpp"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::workflow {

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

// Seconds per stage. read and write are wall time of the one thread doing them; kernels
// (phase, statistics, confidence intervals), psd (PSD, PSD fit, cross-check) and fit (the
// eq. (3) fit) are summed over the channels, so with channels in parallel they add up to more
// than the wall time (analysis_wall, from the first read to the last channel done).
struct StageTimes {
  double read = 0, kernels = 0, psd = 0, fit = 0, write = 0, analysis_wall = 0;
};

/// Wall seconds from `t0` to now, as StageTimes counts them.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// What the caller hears while the run goes, each optional: the run asks `stop` before each
/// recording (a signal number ends the run there, 0 goes on); `started` is told how many
/// recordings there are once the inputs are expanded; `begin` comes before each recording,
/// `done` after it (how many are done, and how many samples this one read; 0 when its results
/// were current), and `written` with each recording's results once they are in OUTDIR.
struct AnalyzeHooks {
  std::function<int()> stop;
  std::function<void(std::size_t n_files)> started;
  std::function<void()> begin;
  std::function<void(std::size_t n_done, std::uint64_t samples)> done;
  std::function<void(const io::RecordingResult& rec, std::size_t n_files)> written;
};

/// What a run did: its exit status of docs/cli.md, and the figures of its closing lines.
struct AnalyzeOutcome {
  int status = kExitOk;       // 0, 1, 2, or 128 + the signal that stopped it
  bool ran = false;           // false: stopped before any input (spec, OUTDIR, a summary clash)
  int stop_signal = 0;        // the signal that stopped the run before its last recording, or 0
  std::size_t n_inputs = 0;   // recordings found and inputs that could not be expanded
  std::size_t n_files = 0;    // recordings found
  std::size_t n_done = 0;     // recordings gone through before the end or the stop
  std::size_t n_ok = 0;       // analysed, or current
  std::size_t n_current = 0;  // of which current (resume)
  int threads = 1;            // threads the run used
  std::uint64_t memory_limit = 0;  // bytes the channels in flight could hold
  StageTimes times;
};

/// Runs the analysis. Failures are named on `err` with file, dataset and reason ("allanlot:
/// error: ..."), notes too unless opt.quiet; the lot overview goes to `out`. Throws OptionError
/// (an INPUT that lists files but is not given as a manifest) and io::UsageError (a text
/// recording that needs an option not given): usage errors found once OUTDIR is made.
AnalyzeOutcome analyze(const AnalyzeOptions& opt, const AnalyzeHooks& hooks, std::ostream& out,
                       std::ostream& err);

}  // namespace allanlot::workflow
