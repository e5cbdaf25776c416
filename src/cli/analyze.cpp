#include "src/cli/analyze.hpp"
#include "src/cli/analyze_edit.hpp"
#include "src/cli/analyze_stamp.hpp"
#include "src/cli/stat_list.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/fingerprint.hpp"
#include "io/paths.hpp"
#include "io/recording.hpp"
#include "io/results.hpp"
#include "io/text_recording.hpp"
#include "kernels/common/parallel.hpp"
#include "kernels/model/units.hpp"
#include "src/cli/input_options.hpp"
#include "src/cli/inputs.hpp"
#include "src/cli/interrupt.hpp"
#include "src/cli/memory.hpp"
#include "src/cli/progress.hpp"
#include "src/cli/resume.hpp"
#include "src/cli/unit_tables.hpp"
#include "src/lot/spec.hpp"
#include "src/lot/summary.hpp"
#include "src/pipeline/channel.hpp"

#include <allanlot/version.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>

namespace fs = std::filesystem;

namespace allanlot::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Seconds per stage. read and write are wall time of the one thread doing them; kernels
// (phase, statistics, confidence intervals), psd (PSD, PSD fit, cross-check) and fit (the
// eq. (3) fit) are summed over the channels, so with channels in parallel they add up to more
// than the wall time (analysis_wall, from the first read to the last channel done).
struct StageTimes {
  double read = 0, kernels = 0, psd = 0, fit = 0, write = 0, analysis_wall = 0;
};

// Bytes one channel of n samples may hold while it is analysed, counted generously: the phase
// (8 n), the rate rebuilt for the PSD (8 n), the fixed-point prefix sums of MDEV/TDEV (8 n) and
// the samples as read (8 n). No stage holds more than two of them at once (the samples are
// freed once the phase is built, the phase before the PSD): the measured peak of a 90-minute
// 1 kHz channel in flight is about 3 x 8 n with the process's own memory (bench_unit.sh).
constexpr std::uint64_t kBytesPerSampleInFlight = 32;

// Reads one channel's samples (callers hold the read lock: HDF5 calls one at a time). On
// failure, `result` is the channel's description with the reason in its status.
bool read_channel(io::RecordingReader& reader, const std::string& file, const io::ChannelInfo& ch,
                  std::uint64_t memory_limit, kernels::LargeVector<double>& samples,
                  io::ChannelResult& result) {
  try {
    // A channel that alone needs more than the memory limit is refused before anything is
    // allocated (a chunked dataset whose chunks were never written declares any length in a
    // few kilobytes), rather than fail the run on the allocation or drive the node into swap.
    if (static_cast<std::uint64_t>(ch.n_samples) > memory_limit / kBytesPerSampleInFlight) {
      // In double: 32 bytes times a declared length of 2^59 or more does not fit 64 bits.
      const auto mib = [](double bytes) {
        const bool gib = bytes >= static_cast<double>(std::uint64_t{1} << 30);
        const double v = bytes / static_cast<double>(gib ? 1 << 30 : 1 << 20);
        char text[48];
        std::snprintf(text, sizeof text, v < 100 ? "%.3g %s" : "%.0f %s", v, gib ? "GiB" : "MiB");
        return std::string(text);
      };
      throw io::Error(file, ch.path,
                      std::to_string(ch.n_samples) + " samples need about " +
                          mib(static_cast<double>(kBytesPerSampleInFlight) *
                              static_cast<double>(ch.n_samples)) +
                          " to analyse (" + std::to_string(kBytesPerSampleInFlight) +
                          " bytes a sample), more than the memory limit of " +
                          mib(static_cast<double>(memory_limit)) +
                          " (--memory-limit; default half of this machine's memory)");
    }
    samples = reader.read(ch);
    return true;
  } catch (const io::Error& e) {
    result = pipeline::describe_channel(ch);
    result.status = io::ChannelStatus::failed(e.reason());
  } catch (const std::exception& e) {
    result = pipeline::describe_channel(ch);
    result.status = io::ChannelStatus::failed(e.what());
  }
  return false;
}

// Units outside the one vocabulary (kernels/model/units.hpp), once per file and unit: the
// channel keeps them, and its coefficients have no datasheet forms.
void warn_unknown_units(const std::string& file, const std::vector<const io::ChannelInfo*>& chs,
                        std::ostream& err) {
  std::map<std::string, std::string> unknown;  // unit -> its channels
  for (const io::ChannelInfo* ch : chs)
    if (!ch->units.empty() && !kernels::units::parse_channel_units(ch->units)) {
      std::string& list = unknown[ch->units];
      list += list.empty() ? "" : ", ";
      list += ch->path;
    }
  for (const auto& [unit, channels] : unknown)
    err << "allanlot: warning: " << file << ": unit '" << unit << "' (" << channels
        << ") is not in allanlot's vocabulary (docs/formats.md#units): its coefficients stay in '"
        << unit << "' and seconds, without datasheet units\n";
}

// What each channel's analysis is asked for (the pipeline's view of the options).
pipeline::ChannelOptions channel_options(const AnalyzeOptions& opt, int kernel_threads) {
  pipeline::ChannelOptions copt;
  copt.stats = opt.stats;
  copt.grid = opt.grid;
  copt.confidence = opt.confidence;
  copt.fit = opt.fit;
  copt.lowpass = pipeline::parse_lowpass_choice(opt.lowpass);
  copt.model.enabled = opt.model_poor_fits == "auto";
  copt.noise_model = pipeline::parse_noise_model(opt.noise_model);
  copt.psd = opt.psd;
  copt.gaps = opt.gaps;
  copt.threads = kernel_threads;
  copt.edit = opt.edit;
  return copt;
}

// The results file's root for a recording, before any channel: who the unit is, where it came
// from, what wrote it and with which options.
io::RecordingResult recording_header(const std::string& file, const io::RecordingInfo& info,
                                     const AnalyzeOptions& opt, int threads) {
  io::RecordingResult rec;
  rec.device_id = info.device_id;
  rec.source_file = fs::absolute(file).string();
  rec.tool_version = std::string(kVersion) + " (" + kGitSha + ")";
  rec.created_utc = utc_now();
  rec.command_line = opt.command_line;
  rec.attributes = {{"stats", join_stats(opt.stats)},
                    {"taus", kernels::to_string(opt.grid)},
                    {"threads", std::to_string(threads)},
                    {"confidence", std::to_string(opt.confidence)},
                    {"git_sha", kGitSha}};
  rec.attributes.insert(rec.attributes.end(), info.facts.begin(), info.facts.end());
  return rec;
}

// The poor fits left by the channels' workers (ChannelOptions::defer_model), modelled as tasks of
// one team, one a channel: a thread that finishes its channel takes the next, and when none is
// left it takes the loops of those still running (their candidates, resonance grid rows and
// replicas are tasks too: kernels::for_each_index), so that the longest channel does not leave a
// core idle. No model depends on its thread count or on which thread ran what
// (ChannelModel.ModelDoesNotDependOnTheThreadCount), so the schedule changes no number.
void model_poor_fits(std::vector<pipeline::ChannelAnalysis>& done,
                     const pipeline::ChannelOptions& copt, int threads) {
  std::vector<pipeline::ChannelAnalysis*> todo;
  for (pipeline::ChannelAnalysis& c : done)
    if (c.deferred) todo.push_back(&c);
  if (todo.empty()) return;
  if (threads <= 1) {
    for (pipeline::ChannelAnalysis* c : todo)
      pipeline::model_deferred(*c, copt, threads);
    return;
  }
#pragma omp parallel num_threads(threads)
#pragma omp single
  for (pipeline::ChannelAnalysis* c : todo) {
#pragma omp task firstprivate(c)
    pipeline::model_deferred(*c, copt, threads);
  }
}

// Analyses one recording. Throws io::Error when the input as a whole cannot be analysed
// (unreadable, no channel, every channel failed); channel failures inside a readable file are
// recorded in the channel's status and reported on `err`. At most
// min(threads, memory_limit / (32 bytes x samples)) channels (at least one) are in memory at
// once, each freed as soon as it is analysed; every kernel is thread-invariant, so neither
// number changes a result. A channel that alone exceeds the limit fails, unread.
io::RecordingResult analyze_recording(const std::string& file, const AnalyzeOptions& opt,
                                      int threads, std::uint64_t memory_limit, StageTimes& times,
                                      std::ostream& err, bool& channel_failed) {
  auto t0 = Clock::now();
  io::RecordingReader reader(file, opt.input);
  const io::RecordingInfo& info = reader.info();
  std::ostream& notes = notes_stream(opt.quiet, err);
  for (const std::string& note : info.notes)
    notes << "allanlot: note: " << file << ": " << note << "\n";

  io::RecordingResult rec = recording_header(file, info, opt, threads);
  for (const io::ChannelProblem& p : info.problems) {
    if (!opt.channels.selects(p.path)) continue;
    io::ChannelResult cr;
    cr.path = p.path;
    cr.status = io::ChannelStatus::failed(p.reason);
    rec.channels.push_back(cr);
    err << "allanlot: error: " << file << ":" << p.path << ": " << p.reason << "\n";
    channel_failed = true;
  }
  std::vector<const io::ChannelInfo*> selected;
  std::int64_t max_samples = 1;
  for (const io::ChannelInfo& ch : info.channels)
    if (opt.channels.selects(ch.path)) {
      selected.push_back(&ch);
      max_samples = std::max(max_samples, ch.n_samples);
    }
  times.read += seconds_since(t0);
  warn_unknown_units(file, selected, notes);
  if (selected.empty() && rec.channels.empty())
    throw io::Error(file, "",
                    opt.channels.selects_all()
                        ? "no channel found (no 1-D numeric dataset with a sample_rate_hz "
                          "attribute on itself or an ancestor group)"
                        : unselected_reason(opt.channels, info));
  note_unmatched(file, opt.channels, info, notes);

  // Channels that fit the limit at once, divided so that nothing overflows: 32 bytes times a
  // declared length of 2^59 samples wraps to 0 in 64 bits. Such a channel fails unread
  // (read_channel), so one slot is enough.
  const std::uint64_t samples_in_limit = memory_limit / kBytesPerSampleInFlight;
  const std::size_t n_selected = selected.size();
  const std::size_t slots = std::clamp<std::size_t>(
      static_cast<std::size_t>(samples_in_limit / static_cast<std::uint64_t>(max_samples)), 1,
      std::max<std::size_t>(n_selected, 1));
  // One level of parallelism (docs/development.md): across channels when there are at least as many
  // channels as threads, otherwise inside the kernels over taus. Each worker takes the next
  // channel, reads it (HDF5 calls one at a time, under read_mutex), hashes it outside the lock
  // (the digests are chained in channel order afterwards, io/fingerprint.hpp), builds its
  // phase, analyses it and frees it: the read of one channel overlaps the analysis of another, and
  // at most `workers` channels are in memory. The kernels give bit-identical results for any thread
  // count, so none of these choices changes a number.
  const bool across = n_selected >= static_cast<std::size_t>(threads) && threads > 1;
  const int workers =
      across ? static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threads), slots))
             : 1;
  const int kernel_threads = std::max(1, threads / workers);
  pipeline::ChannelOptions copt = channel_options(opt, kernel_threads);
  // Poor fits are modelled after the channels (model_poor_fits), when every channel's phase fits
  // the memory limit at once (each deferred model keeps its channel's).
  copt.defer_model = workers > 1 && slots >= n_selected;
  std::vector<pipeline::ChannelAnalysis> done(n_selected);
  std::vector<std::optional<std::uint64_t>> digest(n_selected);  // of the channels read
  std::mutex read_mutex;
  std::size_t next = 0;
  const auto t_analysis = Clock::now();
#pragma omp parallel num_threads(workers)
  for (;;) {
    std::size_t i = 0;
    kernels::LargeVector<double> samples;
    bool read_ok = false;
    {
      const std::lock_guard<std::mutex> lock(read_mutex);
      if (next == n_selected) break;
      i = next++;
      const auto t_read = Clock::now();
      read_ok = read_channel(reader, file, *selected[i], memory_limit, samples, done[i].result);
      times.read += seconds_since(t_read);
    }
    if (!read_ok) continue;
    digest[i] = io::channel_digest(selected[i]->path, samples);
    done[i] = pipeline::analyze_channel(*selected[i], std::move(samples), copt);
  }
  model_poor_fits(done, copt, threads);
  times.analysis_wall += seconds_since(t_analysis);
  for (const pipeline::ChannelAnalysis& c : done) {
    times.kernels += c.times.kernels;
    times.psd += c.times.psd;
    times.fit += c.times.fit;
  }
  std::uint64_t hash = io::kHashSeed;
  for (const std::optional<std::uint64_t>& d : digest)
    if (d) hash = io::combine_hash(hash, *d);
  rec.attributes.emplace_back("input_hash", io::hash_hex(hash));

  std::size_t n_ok = 0;
  for (pipeline::ChannelAnalysis& c : done) {
    if (!c.result.notes.empty())
      notes << "allanlot: note: " << file << ":" << c.result.path << ": " << c.result.notes << "\n";
    if (!c.ok()) {
      err << "allanlot: error: " << file << ":" << c.result.path << ": " << c.result.status.reason
          << "\n";
      channel_failed = true;
    } else {
      ++n_ok;
    }
    rec.channels.push_back(std::move(c.result));
  }
  if (n_ok == 0) {
    std::string reason = "no channel could be analysed";
    if (rec.channels.size() == 1)
      reason += " (" + rec.channels[0].path + ": " + rec.channels[0].status.reason + ")";
    throw io::Error(file, "", reason);
  }
  return rec;
}

// Fails with a usage-level message when OUTDIR cannot hold results.
bool prepare_outdir(const fs::path& outdir, std::ostream& err, std::ostream& notes) {
  std::error_code ec;
  if (fs::exists(outdir, ec) && !fs::is_directory(outdir, ec)) {
    err << "allanlot: error: output directory " << outdir.string()
        << " exists and is not a directory\n";
    return false;
  }
  fs::create_directories(outdir, ec);
  if (ec) {
    err << "allanlot: error: cannot create output directory " << outdir.string() << ": "
        << ec.message() << "\n";
    return false;
  }
  try {
    // Created as every output is (io::AtomicFile: exclusive, never through a planted link) and
    // removed at once.
    const io::AtomicFile probe(outdir / ".allanlot-probe");
  } catch (const io::Error&) {
    err << "allanlot: error: output directory " << outdir.string() << " is not writable\n";
    return false;
  }
  // Temporary files of an earlier run that was killed (SIGKILL, a node lost) are removed;
  // a minute's margin spares those another host is writing right now.
  const std::size_t stale = io::remove_stale_temporaries(outdir, fs::file_time_type::clock::now() -
                                                                     std::chrono::minutes(1));
  if (stale > 0)
    notes << "allanlot: note: removed " << stale << " temporary file(s) of an interrupted run from "
          << outdir.string() << "\n";
  return true;
}

// One run of analyze over its inputs: what is counted and collected as recordings are done.
struct Run {
  Run(const AnalyzeOptions& o, std::ostream& out_stream, std::ostream& err_stream)
      : opt(o), out(out_stream), err(err_stream) {}
  const AnalyzeOptions& opt;
  std::ostream& out;
  std::ostream& err;
  int threads = 1;
  std::uint64_t memory_limit = 0;
  std::string options;  // the resume stamp of these options
  std::vector<fs::path> inputs;
  StageTimes times;
  std::size_t n_ok = 0, n_current = 0;
  bool channel_failed = false;
  std::map<std::string, std::string> used_ids;  // sanitized device id -> file that has it
  std::vector<io::SummaryRow> failed_rows;
  const spec::Spec* spec = nullptr;  // --spec, loaded before the run

  // A failed input's row, named as its results would be: `unit7.csv.gz` is `unit7`.
  void failed(const std::string& file, const std::string& dataset, const std::string& reason) {
    const std::string id =
        io::is_text_name(file) ? io::text_device_id(file) : fs::path(file).stem().string();
    failed_rows.push_back({id, dataset, "", 0, io::ChannelStatus::failed(reason), file});
  }
  void claim_id(const std::string& id, const std::string& file) {
    if (const auto it = used_ids.find(id); it != used_ids.end())
      throw io::Error(file, "",
                      "device_id '" + id + "' is also the device_id of " + it->second +
                          "; its results would overwrite those");
    used_ids.emplace(id, file);
  }
  std::uint64_t analyze_one(const std::string& file, std::size_t n_files);
  void write(const std::string& file, const io::RecordingResult& rec, const std::string& id);
};

// Writes the results of `file`, under the lock of OUTDIR so that the check that no other
// recording owns its device_id and the rename into place are one step for concurrent runs.
void Run::write(const std::string& file, const io::RecordingResult& rec, const std::string& id) {
  const fs::path path = opt.outdir / (id + ".allan.h5");
  if (const auto in = io::replaced_input(path, inputs))
    throw io::Error(file, "", io::replaced_input_message(path, *in));
  std::string hash;
  for (const auto& [k, v] : rec.attributes)
    if (k == "input_hash") hash = v;
  const auto t0 = Clock::now();
  const io::DirectoryLock lock(opt.outdir);
  if (const std::string why = results_of_another_recording(path, file, hash); !why.empty())
    throw io::Error(file, "", why);
  io::write_results(path, rec);
  times.write += seconds_since(t0);
}

// Analyses (or finds current) one recording; returns its samples for the progress line.
std::uint64_t Run::analyze_one(const std::string& file, std::size_t n_files) {
  const auto st = io::stat_input(file);
  if (!opt.force && st) {
    if (const auto cur = current_results(file, *st, options, opt)) {
      claim_id(cur->second, file);
      ++n_ok;
      ++n_current;
      return 0;
    }
  }
  io::RecordingResult rec =
      analyze_recording(file, opt, threads, memory_limit, times, err, channel_failed);
  if (st) {
    rec.attributes.emplace_back("input_size", st->size);
    rec.attributes.emplace_back("input_mtime_ns", st->mtime_ns);
  }
  rec.attributes.emplace_back("options", options);
  std::uint64_t samples = 0;
  for (const auto& ch : rec.channels)
    samples += static_cast<std::uint64_t>(ch.n_samples);
  const std::string id = io::sanitize_device_id(rec.device_id);
  claim_id(id, file);
  write(file, rec, id);
  ++n_ok;
  if (!opt.quiet && (opt.table || n_files <= 10)) out << unit_tables(rec, opt.si);
  return samples;
}

// The lot summary of what OUTDIR holds; false when it could not be written.
bool write_summary(const Run& run) {
  // Another run writing into the same OUTDIR rebuilds the summary too: listing and writing
  // under one lock, the summary written last has seen every results file (io::DirectoryLock).
  const io::DirectoryLock summary_lock(run.opt.outdir);
  std::vector<io::SummaryRow> rows = lot::rows_from_outdir(run.opt.outdir, run.err);
  rows.insert(rows.end(), run.failed_rows.begin(), run.failed_rows.end());
  try {
    lot::LotOptions lot_opt;
    lot_opt.spec_path = run.opt.spec_path;
    lot_opt.spec = run.spec;
    lot_opt.quiet = run.opt.quiet;
    lot::write_lot(run.opt.outdir, std::move(rows), lot_opt, run.out, run.err);
  } catch (const std::exception& e) {
    run.err << "allanlot: error: writing the lot summary: " << e.what() << "\n";
    return false;
  }
  return true;
}

void print_closing(const Run& run, std::size_t n_inputs) {
  const AnalyzeOptions& opt = run.opt;
  const StageTimes& t = run.times;
  if (opt.verbose)
    run.err << "allanlot: stage seconds: read " << t.read << ", kernels " << t.kernels << ", psd "
            << t.psd << ", fit " << t.fit << ", write " << t.write << ", analysis wall "
            << t.analysis_wall << " (" << run.threads
            << " threads; kernels, psd and fit summed over channels); peak memory "
            << peak_rss_bytes() / (1 << 20) << " MiB (budget " << run.memory_limit / (1 << 20)
            << " MiB)\n";
  if (opt.quiet) return;
  run.out << "analysed " << run.n_ok - run.n_current << " of " << n_inputs << " input(s)";
  if (run.n_current)
    run.out << ", " << run.n_current << " already up to date (--force redoes them)";
  run.out << "; results in " << opt.outdir.string() << "\n";
  if (opt.summary)
    run.out << "lot summary: " << (opt.outdir / "lot_summary.csv").string() << " and "
            << (opt.outdir / "lot_summary.h5").string() << "\n";
}

}  // namespace

int run_analyze(const AnalyzeOptions& opt, std::ostream& out, std::ostream& err) {
  // A bad spec is a usage error found before the night's work, not after it: every problem it
  // has is named before OUTDIR is touched or a recording read.
  std::optional<spec::Spec> sp;
  if (!opt.spec_path.empty()) {
    try {
      sp = spec::load_spec(opt.spec_path);
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return 2;
    }
  }
  if (!prepare_outdir(opt.outdir, err, notes_stream(opt.quiet, err))) return 2;
  const InterruptGuard interrupts;
  Run run(opt, out, err);
  run.spec = sp ? &*sp : nullptr;
  run.threads = kernels::resolve_threads(opt.threads);
  run.memory_limit = opt.memory_limit ? opt.memory_limit : physical_memory() / 2;
  const MemoryReuse reuse(run.memory_limit);
  run.options = options_stamp(opt);
  // OUTDIR and the results in it are never inputs, also when OUTDIR lies inside an input.
  const InputList inputs = expand_inputs(opt.inputs, opt.outdir);
  check_inputs_need(inputs.files, opt.input);
  run.inputs.assign(inputs.files.begin(), inputs.files.end());
  // The lot summary never replaces an input (`analyze -o d d/lot_summary.csv`), checked by
  // identity before any work; a results file is checked when its device_id is known.
  if (opt.summary) {
    const auto summary_files = io::lot_summary_files(opt.outdir);
    if (const std::string clash = io::outputs_conflict(summary_files, run.inputs); !clash.empty()) {
      err << "allanlot: error: " << clash << "\n";
      return 2;
    }
  }
  for (const auto& [what, reason] : inputs.failures) {
    err << "allanlot: error: " << what << ": " << reason << "\n";
    run.failed(what, "", reason);
  }
  Progress progress(opt.progress && !opt.quiet, inputs.files.size(), err);
  std::size_t n_done = 0;
  for (const std::string& file : inputs.files) {
    if (stop_signal()) break;
    std::uint64_t samples = 0;
    progress.clear();
    try {
      samples = run.analyze_one(file, inputs.files.size());
    } catch (const io::Error& e) {
      err << "allanlot: error: " << e.what() << "\n";
      run.failed(file, e.dataset(), e.reason());
    } catch (const std::exception& e) {
      err << "allanlot: error: " << file << ": " << e.what() << "\n";
      run.failed(file, "", e.what());
    }
    progress.update(++n_done, samples);
  }
  const bool summary_ok = !opt.summary || write_summary(run);
  const std::size_t n_inputs = inputs.files.size() + inputs.failures.size();
  print_closing(run, n_inputs);
  if (const int sig = stop_signal()) {
    err << "allanlot: stopped by " << signal_name(sig) << " after " << n_done << " of "
        << inputs.files.size() << " recording(s); the results written are complete"
        << (opt.summary ? " and in the lot summary" : "")
        << "; the same command finishes the lot\n";
    return 128 + sig;
  }
  if (run.n_ok == 0) return 2;
  // A summary that could not be written fails the run, not its usage: the results stand.
  return (run.n_ok < n_inputs || run.channel_failed || !summary_ok) ? 1 : 0;
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
      opt.memory_limit = parse_memory_size(a.memory_text);
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
