#include "src/analyze.hpp"

#include "io/error.hpp"
#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan.hpp"
#include "kernels/confidence.hpp"
#include "kernels/parallel.hpp"
#include "kernels/phase.hpp"
#include "kernels/psd.hpp"

#include <allanlot/version.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fnmatch.h>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <unistd.h>

#include "src/channel_fit.hpp"
#include "src/inputs.hpp"

namespace fs = std::filesystem;

namespace allanlot::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

bool channel_selected(const std::string& glob, const std::string& path) {
  if (glob.empty()) return true;
  const std::string name = path.substr(path.find_last_of('/') + 1);
  return fnmatch(glob.c_str(), path.c_str(), 0) == 0 || fnmatch(glob.c_str(), name.c_str(), 0) == 0;
}

struct StageTimes {
  double read = 0, kernels = 0, write = 0;
};

// One channel read into memory and prepared for the kernels.
struct Prepared {
  io::ChannelResult result;
  kernels::PhaseData phase;
  bool ok = false;
};

// The Welch PSD of the channel's rate (psd/, log-binned) and equation (2) applied to it at the
// oadev taus against the time-domain variance (crosscheck/). The rate is rebuilt from the
// phase (mean removed, NaN where an increment is missing) so that phase and rate input are
// treated alike. A record too short for a PSD is a note, not a failure of the channel.
void psd_and_crosscheck(Prepared& c, const kernels::StatResult& oadev, int threads,
                        const std::array<kernels::TermFit, kernels::kNumTerms>* allan_terms) {
  const std::vector<double>& x = c.phase.x;
  std::vector<double> rate(x.size() - 1);
  const double rate_hz = 1.0 / c.phase.tau0_s;
  for (std::size_t k = 0; k + 1 < x.size(); ++k)
    rate[k] = c.phase.clean(static_cast<std::int64_t>(k), static_cast<std::int64_t>(k) + 1)
                  ? (x[k + 1] - x[k]) * rate_hz
                  : std::nan("");
  kernels::PsdResult psd;
  try {
    psd = kernels::welch_psd(rate, rate_hz, threads);
  } catch (const std::invalid_argument& e) {
    c.result.notes += (c.result.notes.empty() ? "" : "; ") + std::string("no PSD: ") + e.what();
    return;
  }
  const kernels::BinnedPsd binned = kernels::log_bin(psd);
  io::PsdRecord pr;
  pr.method = "welch, hann window, 50% overlap, segment length " +
              std::to_string(psd.segment_length) + ", " + std::to_string(psd.n_segments) +
              " segments (" + std::to_string(psd.n_skipped) + " skipped for gaps), log-binned";
  pr.f = binned.f_hz;
  pr.psd = binned.psd;
  pr.edf = binned.edf;
  pr.n_avg = binned.n_avg;
  c.result.psd = std::move(pr);
  c.result.psd_fit = psd_fit_channel(psd, c.result.units, allan_terms);

  const kernels::AvarPsdResult ap = kernels::avar_from_psd(psd, oadev.tau_s, {}, threads);
  io::CrosscheckRecord cc;
  cc.tau = oadev.tau_s;
  cc.avar_psd = ap.avar;
  cc.valid = ap.valid;
  double worst = -1.0;
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    const double avar = oadev.dev[i] * oadev.dev[i];
    cc.avar_time.push_back(avar);
    cc.ratio.push_back(ap.avar[i] / avar);
    if (ap.valid[i] && std::isfinite(cc.ratio.back()) && cc.ratio.back() > 0.0 &&
        std::abs(std::log10(cc.ratio.back())) > worst) {
      worst = std::abs(std::log10(cc.ratio.back()));
      cc.worst_tau = oadev.tau_s[i];
    }
  }
  cc.max_abs_log10_ratio = worst >= 0.0 ? worst : std::nan("");
  cc.valid_tau_range = {ap.tau_valid_min, ap.tau_valid_max};
  c.result.crosscheck = std::move(cc);
}

// Computes every requested statistic of one prepared channel, then the eq. (3) fit of its
// overlapping Allan curve (computed for the fit when not requested: CONTRACT writes fit/
// whatever --stats says). TDEV is derived from MDEV when both are requested (tau/sqrt(3) times
// the same sum, SP1065 eq. (16)) instead of summing the same third differences twice. Throws
// std::exception on a numerical precondition (the caller records it as the channel's failure).
void compute_channel(Prepared& c, const AnalyzeOptions& opt, int kernel_threads) {
  bool any_row = false;
  const kernels::StatResult* mdev = nullptr;
  std::optional<kernels::StatResult> oadev_for_fit;
  c.result.stats.reserve(opt.stats.size());  // `mdev` points into it: no reallocation
  for (const kernels::Stat s : opt.stats) {
    if (c.phase.has_gaps() && !kernels::supports_gaps(s)) {
      // Skipped, not failed: the channel's other statistics stand, and the note says why.
      c.result.notes += (c.result.notes.empty() ? "" : "; ") + std::string(kernels::stat_name(s)) +
                        " not computed: it cannot run on data with gaps (" +
                        std::to_string(c.phase.n_gaps) + " missing samples)";
      continue;
    }
    const auto ms =
        kernels::make_m_list(opt.grid, kernels::max_m(s, c.phase.n_points()), c.phase.n_points());
    kernels::StatResult r = (s == kernels::Stat::Tdev && mdev && mdev->m == ms)
                                ? kernels::tdev_from_mdev(*mdev)
                                : kernels::compute(s, c.phase, ms, kernel_threads);
    kernels::add_confidence(s, c.phase, r, opt.confidence, kernel_threads);
    any_row = any_row || r.size() > 0;
    c.result.stats.emplace_back(std::string(kernels::stat_name(s)), std::move(r));
    if (s == kernels::Stat::Mdev) mdev = &c.result.stats.back().second;
    if (s == kernels::Stat::Oadev) oadev_for_fit = c.result.stats.back().second;
  }
  if (!any_row) {
    c.result.stats.clear();
    throw std::invalid_argument("too short for any tau of the requested statistics (" +
                                std::to_string(c.result.n_samples) + " samples)");
  }
  if (!opt.fit && !opt.psd) return;
  if (!oadev_for_fit) {
    const auto ms = kernels::make_m_list(
        opt.grid, kernels::max_m(kernels::Stat::Oadev, c.phase.n_points()), c.phase.n_points());
    oadev_for_fit = kernels::compute(kernels::Stat::Oadev, c.phase, ms, kernel_threads);
    kernels::add_confidence(kernels::Stat::Oadev, c.phase, *oadev_for_fit, opt.confidence,
                            kernel_threads);
  }
  std::array<kernels::TermFit, kernels::kNumTerms> allan_terms{};
  bool have_allan_terms = false;
  if (opt.fit) {
    c.result.fit = fit_channel(*oadev_for_fit, c.phase, c.result.units, &allan_terms);
    have_allan_terms = c.result.fit->status == kernels::fit_status_name(kernels::FitStatus::Ok);
  }
  if (opt.psd)
    psd_and_crosscheck(c, *oadev_for_fit, kernel_threads,
                       have_allan_terms ? &allan_terms : nullptr);
}

std::string join_stats(const std::vector<kernels::Stat>& stats) {
  std::string s;
  for (std::size_t i = 0; i < stats.size(); ++i)
    s += (i ? "," : "") + std::string(kernels::stat_name(stats[i]));
  return s;
}

// Analyses one recording. Throws io::Error when the input as a whole cannot be analysed
// (unreadable, no channel, every channel failed); channel failures inside a readable file are
// recorded in the channel's status and reported on `err`.
io::RecordingResult analyze_recording(const std::string& file, const AnalyzeOptions& opt,
                                      int threads, StageTimes& times, std::ostream& err,
                                      bool& channel_failed) {
  auto t0 = Clock::now();
  io::RecordingReader reader(file);
  const io::RecordingInfo& info = reader.info();

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

  std::vector<Prepared> work;
  for (const io::ChannelProblem& p : info.problems) {
    if (!channel_selected(opt.channels_glob, p.path)) continue;
    io::ChannelResult cr;
    cr.path = p.path;
    cr.status = "failed: " + p.reason;
    rec.channels.push_back(cr);
    err << "allanlot: error: " << file << ":" << p.path << ": " << p.reason << "\n";
    channel_failed = true;
  }
  for (const io::ChannelInfo& ch : info.channels) {
    if (!channel_selected(opt.channels_glob, ch.path)) continue;
    Prepared c;
    c.result.path = ch.path;
    c.result.units = ch.units;
    c.result.sample_rate_hz = ch.sample_rate_hz;
    c.result.n_samples = ch.n_samples;
    c.result.data_type = ch.data_type == kernels::DataType::Rate ? "rate" : "phase";
    try {
      const std::vector<double> samples = reader.read(ch);
      c.phase = kernels::make_phase(samples, ch.data_type, ch.sample_rate_hz, threads);
      c.result.n_gaps = c.phase.n_gaps;
      c.ok = true;
    } catch (const io::Error& e) {
      c.result.status = "failed: " + e.reason();
    } catch (const std::exception& e) {
      c.result.status = std::string("failed: ") + e.what();
    }
    work.push_back(std::move(c));
  }
  times.read += seconds_since(t0);
  if (work.empty() && rec.channels.empty())
    throw io::Error(file, "",
                    opt.channels_glob.empty()
                        ? "no channel found (no 1-D numeric dataset with a sample_rate_hz "
                          "attribute on itself or an ancestor group)"
                        : "no channel matches --channels '" + opt.channels_glob + "'");

  // One level of parallelism (STYLE.md): across channels when there are at least as many
  // channels as threads, otherwise inside the kernels over taus. The kernels give
  // bit-identical results for any thread count, so the choice never changes a number.
  t0 = Clock::now();
  const auto n = static_cast<std::int64_t>(work.size());
  const bool across = n >= threads && threads > 1;
  const int kernel_threads = across ? 1 : threads;
#pragma omp parallel for num_threads(across ? threads : 1) schedule(dynamic, 1)
  for (std::int64_t i = 0; i < n; ++i) {
    Prepared& c = work[static_cast<std::size_t>(i)];
    if (!c.ok) continue;
    try {
      compute_channel(c, opt, kernel_threads);
    } catch (const std::exception& e) {
      c.result.status = std::string("failed: ") + e.what();
      c.ok = false;
    } catch (...) {
      c.result.status = "failed: unexpected error";
      c.ok = false;
    }
    c.phase = kernels::PhaseData{};  // free the channel's memory as soon as it is done
  }
  times.kernels += seconds_since(t0);

  std::size_t n_ok = 0;
  for (Prepared& c : work) {
    if (!c.result.notes.empty())
      err << "allanlot: note: " << file << ":" << c.result.path << ": " << c.result.notes << "\n";
    if (!c.ok) {
      err << "allanlot: error: " << file << ":" << c.result.path << ": "
          << c.result.status.substr(8) << "\n";
      channel_failed = true;
    } else {
      ++n_ok;
    }
    rec.channels.push_back(std::move(c.result));
  }
  if (n_ok == 0) {
    std::string reason = "no channel could be analysed";
    if (rec.channels.size() == 1)
      reason += " (" + rec.channels[0].path + ": " + rec.channels[0].status.substr(8) + ")";
    throw io::Error(file, "", reason);
  }
  return rec;
}

// The lot summary is rebuilt from the complete results files present in OUTDIR, so it is
// consistent with them whatever ran before (earlier runs, other Slurm tasks).
std::vector<io::SummaryRow> rows_from_outdir(const fs::path& outdir, std::ostream& err) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(outdir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".") || !name.ends_with(".allan.h5")) continue;
    files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<io::SummaryRow> rows;
  for (const fs::path& f : files) {
    try {
      for (auto& r : io::summary_rows(io::read_results(f)))
        rows.push_back(std::move(r));
    } catch (const std::exception& e) {
      err << "allanlot: warning: skipping unreadable results file " << f.string() << ": "
          << e.what() << "\n";
    }
  }
  return rows;
}

// Fails with a usage-level message when OUTDIR cannot hold results.
bool prepare_outdir(const fs::path& outdir, std::ostream& err) {
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
  const fs::path probe = outdir / (".allanlot-probe." + std::to_string(::getpid()));
  {
    std::ofstream f(probe);
    if (!f) {
      err << "allanlot: error: output directory " << outdir.string() << " is not writable\n";
      return false;
    }
  }
  fs::remove(probe, ec);
  return true;
}

}  // namespace

int run_analyze(const AnalyzeOptions& opt, std::ostream& out, std::ostream& err) {
  if (!prepare_outdir(opt.outdir, err)) return 2;
  const int threads = kernels::resolve_threads(opt.threads);
  const InputList inputs = expand_inputs(opt.inputs);
  std::vector<io::SummaryRow> failed_rows;
  for (const auto& [what, reason] : inputs.failures) {
    err << "allanlot: error: " << what << ": " << reason << "\n";
    failed_rows.push_back({fs::path(what).stem().string(), "", "", 0, "failed: " + reason, what});
  }

  StageTimes times;
  std::size_t n_ok = 0;
  bool channel_failed = false;
  std::map<std::string, std::string> used_ids;  // sanitized device id -> file that has it
  for (const std::string& file : inputs.files) {
    try {
      io::RecordingResult rec = analyze_recording(file, opt, threads, times, err, channel_failed);
      const std::string id = io::sanitize_device_id(rec.device_id);
      if (const auto it = used_ids.find(id); it != used_ids.end())
        throw io::Error(file, "",
                        "device_id '" + rec.device_id + "' is also the device_id of " + it->second +
                            "; its results would overwrite those");
      used_ids.emplace(id, file);
      const auto t0 = Clock::now();
      io::write_results(opt.outdir / (id + ".allan.h5"), rec);
      times.write += seconds_since(t0);
      ++n_ok;
      if (!opt.quiet && (opt.table || inputs.files.size() <= 10)) out << fit_table(rec);
    } catch (const io::Error& e) {
      err << "allanlot: error: " << e.what() << "\n";
      failed_rows.push_back(
          {fs::path(file).stem().string(), e.dataset(), "", 0, "failed: " + e.reason(), file});
    } catch (const std::exception& e) {
      err << "allanlot: error: " << file << ": " << e.what() << "\n";
      failed_rows.push_back(
          {fs::path(file).stem().string(), "", "", 0, std::string("failed: ") + e.what(), file});
    }
  }

  std::vector<io::SummaryRow> rows = rows_from_outdir(opt.outdir, err);
  rows.insert(rows.end(), failed_rows.begin(), failed_rows.end());
  try {
    io::write_lot_summary(opt.outdir, rows);
  } catch (const std::exception& e) {
    err << "allanlot: error: writing the lot summary: " << e.what() << "\n";
    return 2;
  }
  const std::size_t n_inputs = inputs.files.size() + inputs.failures.size();
  if (opt.verbose)
    err << "allanlot: stage seconds: read " << times.read << ", kernels " << times.kernels
        << ", write " << times.write << " (" << threads << " threads)\n";
  if (!opt.quiet)
    out << "analysed " << n_ok << " of " << n_inputs << " input(s); results in "
        << opt.outdir.string() << "\nlot summary: " << (opt.outdir / "lot_summary.csv").string()
        << " and " << (opt.outdir / "lot_summary.h5").string() << "\n";
  if (n_ok == 0) return 2;
  return (n_ok < n_inputs || channel_failed) ? 1 : 0;
}

int run_summarize(const fs::path& outdir, bool quiet, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(outdir, ec)) {
    err << "allanlot: error: " << outdir.string() << " is not a directory\n";
    return 2;
  }
  const std::vector<io::SummaryRow> rows = rows_from_outdir(outdir, err);
  try {
    io::write_lot_summary(outdir, rows);
  } catch (const std::exception& e) {
    err << "allanlot: error: writing the lot summary: " << e.what() << "\n";
    return 2;
  }
  if (!quiet)
    out << "lot summary of " << rows.size()
        << " channel(s): " << (outdir / "lot_summary.csv").string() << "\n";
  return rows.empty() ? 2 : 0;
}

}  // namespace allanlot::cli
