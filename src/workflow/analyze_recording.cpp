#include "src/workflow/analyze_recording.hpp"

#include "io/error.hpp"
#include "io/fingerprint.hpp"
#include "io/recording.hpp"
#include "kernels/common/parallel.hpp"
#include "kernels/model/units.hpp"
#include "src/pipeline/channel.hpp"
#include "src/workflow/analyze_stamp.hpp"
#include "src/workflow/notes.hpp"
#include "src/workflow/provenance.hpp"

#include <allanlot/version.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>

namespace fs = std::filesystem;

namespace allanlot::workflow {
namespace {

using Clock = std::chrono::steady_clock;

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
  rec.tool_version = tool_version();
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

}  // namespace

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

}  // namespace allanlot::workflow
