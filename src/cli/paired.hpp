// What `allanlot hat` and `allanlot codev` share (docs/cli.md "Command: hat", "Command:
// codev"): statistics of clocks measured in pairs, on several recordings at once. Their
// options, the reading and checking of one channel per recording (same rate, length, data type
// and units, enough points), and the results file they write through io::write_results
// (docs/formats.md "Results files of hat and codev").
#pragma once

#include "io/input_options.hpp"
#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "src/cli/input_options.hpp"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::cli {

struct PairedOptions {
  std::vector<std::string> inputs;  // the recordings, in the command's order
  std::filesystem::path output;     // -o: the results file
  std::string channel;              // --channel: path or name; "" = each file's only channel
  kernels::TauGridSpec grid;        // --taus, as analyze
  double confidence = 0.683;        // --confidence, as analyze
  int threads = 0;                  // --threads; 0 = OMP_NUM_THREADS, else all cores
  io::InputOptions input;           // --data-type and the options of text recordings
  std::string command_line;         // recorded in the results file
};

/// The options as given, before they are checked.
struct PairedArgs {
  PairedOptions opt;
  std::string taus_text = kernels::to_string(kernels::TauGridSpec{});
  std::string output;
  InputArgs input;
};

/// Adds INPUT..., -o, --channel, --taus, --confidence, --threads and the input options.
void add_paired_options(CLI::App* sub, PairedArgs& args);

/// The checked options: CLI::ValidationError (a usage error) for a bad tau grid, for a number of
/// inputs other than `count` (naming the command and the inputs given) or a bad input option.
PairedOptions checked_paired_options(const PairedArgs& args, const std::string& command_line,
                                     std::size_t count, const std::string& command);

/// A usage-level failure of these commands (exit status 2): what a run with other arguments
/// could fix, named with the file and the reason.
struct PairedUsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One recording's channel, read and turned into phase points.
struct PairedRecord {
  std::string file;
  std::string device_id;
  io::ChannelInfo channel;
  kernels::PhaseData phase;
};

/// Reads the selected channel of every input: PairedUsageError naming the file (and channel)
/// when the channel is missing or ambiguous, when a record's sample rate, number of samples,
/// data type or units differ from the first's, when it gives no tau (fewer than 5 phase points:
/// OADEV's largest m, (N - 1) / 4, is 0), or when its samples cannot be turned into phase (all
/// missing, infinite). io::Error when a file cannot be read.
std::vector<PairedRecord> read_paired_records(const PairedOptions& opt);

/// The averaging factors of the run: the tau grid up to OADEV's largest m on N points.
std::vector<std::int64_t> paired_m_list(const PairedOptions& opt, std::int64_t n_points);

/// A channel group of the results file at `path` for a record: its units, rate, samples, gaps
/// and data type, status ok, and `stat_name` -> `stat` under allan/.
io::ChannelResult paired_channel(const PairedRecord& r, const std::string& path,
                                 const std::string& stat_name, const kernels::StatResult& stat);

/// The root of the results file: device ids and source files of the inputs (joined by "; "),
/// version, time, command line, and the attributes `statistic`, `taus`, `confidence`,
/// `threads`, `git_sha`, `channels` (the channels read, "file:path; ...").
io::RecordingResult paired_root(const PairedOptions& opt, const std::vector<PairedRecord>& records,
                                const std::string& statistic);

/// Runs `work` (which reads, computes and writes) and turns its failures into the exit status of
/// docs/cli.md: 2 for PairedUsageError, io::UsageError and an output that would replace an input;
/// 1 for an unreadable input or an output that cannot be written; each named on `err`.
int run_paired(const PairedOptions& opt, std::ostream& err, const std::function<void()>& work);

}  // namespace allanlot::cli
