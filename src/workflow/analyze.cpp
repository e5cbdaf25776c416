#include "src/workflow/analyze.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/fingerprint.hpp"
#include "io/paths.hpp"
#include "io/recording.hpp"
#include "io/text_recording.hpp"
#include "kernels/common/parallel.hpp"
#include "src/lot/spec.hpp"
#include "src/lot/summary.hpp"
#include "src/workflow/analyze_recording.hpp"
#include "src/workflow/analyze_stamp.hpp"
#include "src/workflow/memory.hpp"
#include "src/workflow/notes.hpp"
#include "src/workflow/resume.hpp"

#include <map>
#include <optional>
#include <ostream>

namespace fs = std::filesystem;

namespace allanlot::workflow {
namespace {

using Clock = std::chrono::steady_clock;

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

// One run of analyze over its inputs: what its options make of this machine, and what is counted
// and collected as recordings are done.
struct Run {
  Run(const AnalyzeOptions& o, const spec::Spec* s, std::ostream& out_stream,
      std::ostream& err_stream)
      : opt(o), out(out_stream), err(err_stream), threads(kernels::resolve_threads(o.threads)),
        memory_limit(o.memory_limit ? o.memory_limit : physical_memory() / 2),
        options(options_stamp(o)), spec(s) {}
  const AnalyzeOptions& opt;
  std::ostream& out;
  std::ostream& err;
  const int threads;
  const std::uint64_t memory_limit;
  const std::string options;  // the resume stamp of these options
  const spec::Spec* spec;     // --spec, loaded before the run
  std::vector<fs::path> inputs;
  StageTimes times;
  std::size_t n_ok = 0, n_current = 0;
  bool channel_failed = false;
  std::map<std::string, std::string> used_ids;  // sanitized device id -> file that has it
  std::vector<io::SummaryRow> failed_rows;

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
  std::uint64_t analyze_one(const std::string& file, std::size_t n_files,
                            const AnalyzeHooks& hooks);
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
std::uint64_t Run::analyze_one(const std::string& file, std::size_t n_files,
                               const AnalyzeHooks& hooks) {
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
  if (hooks.written) hooks.written(rec, n_files);
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

}  // namespace

AnalyzeOutcome analyze(const AnalyzeOptions& opt, const AnalyzeHooks& hooks, std::ostream& out,
                       std::ostream& err) {
  AnalyzeOutcome o;
  o.status = kExitUsage;
  std::ostream& notes = notes_stream(opt.quiet, err);
  // A bad spec is a usage error found before the night's work, not after it: every problem it
  // has is named before OUTDIR is touched or a recording read.
  std::optional<spec::Spec> sp;
  if (!opt.spec_path.empty()) {
    try {
      sp = spec::load_spec(opt.spec_path);
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return o;
    }
  }
  if (!prepare_outdir(opt.outdir, err, notes)) return o;
  Run run(opt, sp ? &*sp : nullptr, out, err);
  const MemoryReuse reuse(run.memory_limit);
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
      return o;
    }
  }
  for (const auto& [what, reason] : inputs.failures) {
    err << "allanlot: error: " << what << ": " << reason << "\n";
    run.failed(what, "", reason);
  }
  o.ran = true;
  o.n_files = inputs.files.size();
  o.n_inputs = inputs.files.size() + inputs.failures.size();
  if (hooks.started) hooks.started(o.n_files);
  for (const std::string& file : inputs.files) {
    if (hooks.stop && hooks.stop() != 0) break;
    std::uint64_t samples = 0;
    if (hooks.begin) hooks.begin();
    try {
      samples = run.analyze_one(file, o.n_files, hooks);
    } catch (const io::Error& e) {
      err << "allanlot: error: " << e.what() << "\n";
      run.failed(file, e.dataset(), e.reason());
    } catch (const std::exception& e) {
      err << "allanlot: error: " << file << ": " << e.what() << "\n";
      run.failed(file, "", e.what());
    }
    ++o.n_done;
    if (hooks.done) hooks.done(o.n_done, samples);
  }
  const bool summary_ok = !opt.summary || write_summary(run);
  // Asked again once the summary is written: a signal during the last recording or the summary
  // stops nothing more, but the run it came to is told as stopped.
  o.stop_signal = hooks.stop ? hooks.stop() : 0;
  o.n_ok = run.n_ok;
  o.n_current = run.n_current;
  o.threads = run.threads;
  o.memory_limit = run.memory_limit;
  o.times = run.times;
  if (o.stop_signal)
    o.status = 128 + o.stop_signal;
  else if (run.n_ok == 0)
    o.status = kExitUsage;
  else  // A summary that could not be written fails the run, not its usage: the results stand.
    o.status =
        (run.n_ok < o.n_inputs || run.channel_failed || !summary_ok) ? kExitSomeFailed : kExitOk;
  return o;
}

}  // namespace allanlot::workflow
