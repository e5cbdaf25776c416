#include "src/cli/paired.hpp"

#include "io/error.hpp"
#include "io/paths.hpp"
#include "io/usage_error.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/common/parallel.hpp"
#include "src/cli/cli.hpp"
#include "src/workflow/provenance.hpp"

#include <allanlot/version.hpp>

#include <cmath>
#include <ostream>

namespace allanlot::cli {
namespace {

std::string data_type_text(kernels::DataType t) {
  return t == kernels::DataType::Phase ? "phase" : "rate";
}

// The channel `wanted` names (its path or its last component), or the only channel when
// `wanted` is empty; PairedUsageError naming the file otherwise.
const io::ChannelInfo& select_channel(const io::RecordingInfo& info, const std::string& wanted) {
  for (const io::ChannelProblem& p : info.problems) {
    const std::string name = p.path.substr(p.path.find_last_of('/') + 1);
    if (!wanted.empty() && (p.path == wanted || name == wanted))
      throw PairedUsageError(info.file + ":" + p.path + ": " + p.reason);
  }
  const io::ChannelInfo* found = nullptr;
  std::string names;
  for (const io::ChannelInfo& c : info.channels) {
    names += (names.empty() ? "" : ", ") + c.path;
    const std::string name = c.path.substr(c.path.find_last_of('/') + 1);
    if (wanted.empty() ? info.channels.size() == 1 : (c.path == wanted || name == wanted))
      found = &c;
  }
  if (found) return *found;
  if (wanted.empty())
    throw PairedUsageError(info.file + ": " +
                           (info.channels.empty()
                                ? std::string("no channel")
                                : "several channels (" + names + "); choose one with --channel"));
  throw PairedUsageError(info.file + ": no channel '" + wanted +
                         "' (channels: " + (names.empty() ? "none" : names) + ")");
}

// PairedUsageError when record r cannot be paired with the first record f.
void check_pairs_with(const PairedRecord& f, const PairedRecord& r) {
  const std::string where = r.file + ":" + r.channel.path + ": ";
  const std::string first = " (" + f.file + ":" + f.channel.path + ")";
  if (std::fabs(r.channel.sample_rate_hz / f.channel.sample_rate_hz - 1.0) > 1e-12)
    throw PairedUsageError(where + "sample rate " + std::to_string(r.channel.sample_rate_hz) +
                           " Hz differs from the first record's " +
                           std::to_string(f.channel.sample_rate_hz) + " Hz" + first);
  if (r.channel.n_samples != f.channel.n_samples)
    throw PairedUsageError(
        where + std::to_string(r.channel.n_samples) + " samples where the first record has " +
        std::to_string(f.channel.n_samples) + first + "; the records must cover the same epochs");
  if (r.channel.data_type != f.channel.data_type)
    throw PairedUsageError(where + "data type " + data_type_text(r.channel.data_type) +
                           " differs from the first record's " +
                           data_type_text(f.channel.data_type) + first);
  if (r.channel.units != f.channel.units)
    throw PairedUsageError(where + "units '" + r.channel.units +
                           "' differ from the first record's '" + f.channel.units + "'" + first);
}

}  // namespace

void add_paired_options(CLI::App* sub, PairedArgs& a) {
  sub->add_option("inputs", a.opt.inputs, "Recordings (HDF5 or text)");
  sub->add_option("-o,--output", a.output, "The results file to write (HDF5)")->required();
  sub->add_option("--channel", a.opt.channel,
                  "Channel path or name in every recording (default: each file's only channel)");
  sub->add_option("--taus", a.taus_text,
                  "Tau grid: octave, decade, all, stable32, stable32:K, log:K or m:LIST")
      ->capture_default_str();
  sub->add_option("--confidence", a.opt.confidence,
                  "Confidence level of the intervals dev_lo, dev_hi")
      ->check(finite_number() & CLI::Range(0.001, 0.999))
      ->capture_default_str();
  sub->add_option("--threads", a.opt.threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  add_input_options(sub, a.input);
}

PairedOptions checked_paired_options(const PairedArgs& a, const std::string& command_line,
                                     std::size_t count, const std::string& command) {
  PairedOptions opt = a.opt;
  try {
    opt.grid = kernels::parse_tau_grid(a.taus_text);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--taus", e.what());
  }
  if (opt.inputs.size() != count) {
    std::string given;
    for (const std::string& f : opt.inputs)
      given += (given.empty() ? "" : ", ") + f;
    throw CLI::ValidationError(
        "INPUT", command + " needs exactly " + std::to_string(count) + " recordings, got " +
                     std::to_string(opt.inputs.size()) + (given.empty() ? "" : " (" + given + ")"));
  }
  opt.output = a.output;
  opt.input = input_options(a.input);
  opt.command_line = command_line;
  return opt;
}

std::vector<PairedRecord> read_paired_records(const PairedOptions& opt) {
  std::vector<PairedRecord> out;
  for (const std::string& file : opt.inputs) {
    if (const std::string problem = io::input_file_problem(file); !problem.empty())
      throw PairedUsageError(file + ": " + problem);
    const io::RecordingReader reader(file, opt.input);
    PairedRecord r;
    r.file = file;
    r.device_id = reader.info().device_id;
    r.channel = select_channel(reader.info(), opt.channel);
    if (!out.empty()) check_pairs_with(out.front(), r);
    const kernels::LargeVector<double> samples = reader.read(r.channel);
    try {
      r.phase =
          kernels::make_phase(samples, r.channel.data_type, r.channel.sample_rate_hz, opt.threads);
    } catch (const std::invalid_argument& e) {
      throw PairedUsageError(file + ":" + r.channel.path + ": " + e.what());
    }
    if (kernels::max_m(kernels::Stat::Oadev, r.phase.n_points()) < 1)
      throw PairedUsageError(file + ":" + r.channel.path + ": " +
                             std::to_string(r.channel.n_samples) + " samples give " +
                             std::to_string(r.phase.n_points()) +
                             " phase points, no tau: at least 5 phase points are needed");
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<std::int64_t> paired_m_list(const PairedOptions& opt, std::int64_t n_points) {
  return kernels::make_m_list(opt.grid, kernels::max_m(kernels::Stat::Oadev, n_points), n_points);
}

io::ChannelResult paired_channel(const PairedRecord& r, const std::string& path,
                                 const std::string& stat_name, const kernels::StatResult& stat) {
  io::ChannelResult ch;
  ch.path = path;
  ch.units = r.channel.units;
  ch.sample_rate_hz = r.channel.sample_rate_hz;
  ch.n_samples = r.channel.n_samples;
  ch.n_gaps = r.phase.n_gaps;
  // As analyze writes it (docs/formats.md): a rate neither the file nor --data-type named.
  ch.data_type =
      r.channel.data_type_default ? "rate (default)" : data_type_text(r.channel.data_type);
  ch.status = io::ChannelStatus::ok();
  ch.stats.emplace_back(stat_name, stat);
  return ch;
}

io::RecordingResult paired_root(const PairedOptions& opt, const std::vector<PairedRecord>& records,
                                const std::string& statistic) {
  io::RecordingResult rec;
  std::string channels;
  for (const PairedRecord& r : records) {
    const std::string sep = rec.device_id.empty() ? "" : "; ";
    rec.device_id += sep + r.device_id;
    rec.source_file += sep + std::filesystem::absolute(r.file).string();
    channels += sep + r.file + ":" + r.channel.path;
  }
  rec.tool_version = workflow::tool_version();
  rec.created_utc = workflow::utc_now();
  rec.command_line = opt.command_line;
  rec.attributes = {{"statistic", statistic},
                    {"taus", kernels::to_string(opt.grid)},
                    {"confidence", std::to_string(opt.confidence)},
                    {"threads", std::to_string(kernels::resolve_threads(opt.threads))},
                    {"git_sha", kGitSha},
                    {"channels", channels}};
  return rec;
}

int run_paired(const PairedOptions& opt, std::ostream& err, const std::function<void()>& work) {
  try {
    std::vector<std::filesystem::path> read(opt.inputs.begin(), opt.inputs.end());
    const std::filesystem::path outputs[] = {opt.output};
    if (const std::string clash = io::outputs_conflict(outputs, read); !clash.empty())
      throw PairedUsageError(clash);
    for (const std::string& f : opt.inputs)
      io::check_input_options(f, opt.input);
    work();
    return kExitOk;
  } catch (const PairedUsageError& e) {
    err << "allanlot: usage error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const io::UsageError& e) {
    err << "allanlot: usage error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitSomeFailed;
  }
}

}  // namespace allanlot::cli
