#include "src/workflow/watch.hpp"

#include "io/growing.hpp"
#include "io/recording.hpp"
#include "kernels/common/parallel.hpp"
#include "kernels/model/units.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/plan/sequential.hpp"
#include "src/lot/spec.hpp"
#include "src/pipeline/channel_fit.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;

namespace allanlot::workflow {
namespace {

namespace units = kernels::units;
using spec::Outcome;

// One limited term of a watched channel and what the looks decided of it.
struct Limit {
  spec::TermLimit l;
  std::optional<double> min, max;  // channel units
  Outcome outcome = Outcome::Undecided;
  double decided_at_s = 0;
};

struct Watched {
  io::ChannelInfo info;
  std::string name;
  std::vector<Limit> limits;
};

// The channels the spec covers, with their limits in the channel's units.
std::vector<Watched> watched_channels(const io::RecordingInfo& info, const spec::Spec& s) {
  std::vector<Watched> out;
  for (const io::ChannelInfo& ch : info.channels) {
    const spec::Rule* rule = spec::find_rule(s, ch.path);
    if (!rule || rule->limits.empty()) continue;
    Watched w{ch, ch.path.substr(ch.path.rfind('/') + 1), {}};
    for (const spec::TermLimit& l : rule->limits) {
      const std::string to = units::channel_unit(l.term, ch.units);
      Limit lim{l, {}, {}, Outcome::Undecided, 0};
      if (l.min) lim.min = spec::convert(l.term, *l.min, l.unit, to, ch.units);
      if (l.max) lim.max = spec::convert(l.term, *l.max, l.unit, to, ch.units);
      w.limits.push_back(lim);
    }
    out.push_back(std::move(w));
  }
  return out;
}

const char* outcome_name(Outcome o) {
  return o == Outcome::Pass ? "pass" : o == Outcome::Fail ? "fail" : "undecided";
}

// "N 0.12±0.03 deg/sqrt(h)": the estimate and its half-width at k, in the limit's unit.
std::string estimate_text(const Limit& lim, const kernels::TermFit& t, double k,
                          const std::string& channel_units) {
  const std::string from = units::channel_unit(lim.l.term, channel_units);
  const double v = spec::convert(lim.l.term, t.value, from, lim.l.unit, channel_units);
  const double s = spec::convert(lim.l.term, t.sigma, from, lim.l.unit, channel_units);
  std::ostringstream o;
  o << units::term_name(lim.l.term) << " " << std::setprecision(4) << v << "±" << k * s << " "
    << lim.l.unit;
  return o.str();
}

// Judges the first t seconds of every channel at quantile k; prints what this look decided.
void look(const io::RecordingReader& reader, std::vector<Watched>& ws, double t, double k,
          int threads, std::ostream& out) {
  for (Watched& w : ws) {
    bool open = false;
    for (const Limit& l : w.limits)
      open = open || l.outcome == Outcome::Undecided;
    if (!open) continue;
    const auto all = reader.read(w.info);
    const auto n = std::min<std::size_t>(all.size(), std::llround(t * w.info.sample_rate_hz));
    const LookFit f = look_fit(std::span<const double>(all.data(), n), w.info.sample_rate_hz,
                               w.info.units, threads);
    for (Limit& l : w.limits) {
      if (l.outcome != Outcome::Undecided) continue;
      const kernels::TermFit& tf = f.terms[static_cast<std::size_t>(l.l.term)];
      // A fit whose model misses the curve decides nothing (as spec::judge): its sigmas hold
      // only for the model.
      if (f.status != kernels::FitStatus::Ok) continue;
      // Undetected: the interval [0, value + k sigma] (upper NaN), at this look's k.
      const spec::Estimate e{tf.value, tf.sigma, std::nan(""), tf.detected};
      l.outcome = spec::decide(e, l.min, l.max, k);
      if (l.outcome == Outcome::Undecided) continue;
      l.decided_at_s = t;
      out << "  " << w.name << " " << units::term_name(l.l.term) << " " << outcome_name(l.outcome)
          << ": " << estimate_text(l, tf, k, w.info.units) << "\n";
    }
  }
}

// The watched channels' shortest length in seconds.
double recorded_s(const std::vector<Watched>& ws) {
  double s = INFINITY;
  for (const Watched& w : ws)
    s = std::min(s, static_cast<double>(w.info.n_samples) / w.info.sample_rate_hz);
  return s;
}

// The limits still undecided, "gyro_x N, gyro_x B".
std::string undecided(const std::vector<Watched>& ws) {
  std::string s;
  for (const Watched& w : ws)
    for (const Limit& l : w.limits)
      if (l.outcome == Outcome::Undecided)
        s += (s.empty() ? "" : ", ") + w.name + " " + std::string(units::term_name(l.l.term));
  return s;
}

// `fresh` (from a newer snapshot) with the decisions already taken in `old`: a decided limit
// stays decided.
std::vector<Watched> carried_over(std::vector<Watched> fresh, const std::vector<Watched>& old) {
  for (Watched& w : fresh)
    for (const Watched& o : old)
      if (o.info.path == w.info.path && o.limits.size() == w.limits.size())
        for (std::size_t i = 0; i < w.limits.size(); ++i) {
          w.limits[i].outcome = o.limits[i].outcome;
          w.limits[i].decided_at_s = o.limits[i].decided_at_s;
        }
  return fresh;
}

}  // namespace

LookFit look_fit(std::span<const double> rate, double rate_hz, const std::string& units,
                 int threads) {
  const kernels::StatResult oadev = kernels::record_curve(rate, rate_hz, threads);
  LookFit f;
  const io::FitRecord rec = pipeline::fit_channel(
      oadev, 1.0 / rate_hz, static_cast<std::int64_t>(rate.size()), units, {}, &f.terms, threads);
  f.status = rec.status;
  return f;
}

int run_watch(const WatchOptions& opt, std::ostream& out, std::ostream& err) {
  spec::Spec s;
  io::InputOptions input;
  try {
    s = spec::load_spec(opt.spec_path);
    input = checked_input_options(opt.input);
  } catch (const std::exception&) {
    return print_usage_error(std::current_exception(), err);
  }
  const double alpha = 1.0 - (opt.confidence > 0.0 ? opt.confidence : s.confidence);
  const int threads = kernels::resolve_threads(opt.threads);
  const fs::path dir = fs::temp_directory_path() / ("allanlot-watch-" + std::to_string(getpid()));
  // Two snapshot folders used in turn: the reader of the last look keeps its snapshot open (the
  // HDF5 library refuses to recreate an open file), so the next one is written beside it.
  const fs::path halves[2] = {dir / "a", dir / "b"};
  for (const fs::path& h : halves)
    fs::create_directories(h);
  int generation = 0;
  const auto cleanup =
      std::unique_ptr<const fs::path, void (*)(const fs::path*)>(&dir, [](const fs::path* d) {
        std::error_code ec;
        fs::remove_all(*d, ec);
      });
  std::uintmax_t seen = 0;
  std::unique_ptr<io::RecordingReader> reader;
  std::vector<Watched> ws;
  double prev = 0.0;
  const int looks = static_cast<int>(std::ceil(opt.max_duration_s / opt.interval_s - 1e-9));
  out << "watching " << opt.recording << " against " << opt.spec_path << ": a look every "
      << opt.interval_s << " s up to " << opt.max_duration_s << " s (" << looks
      << " looks, error rate " << alpha << " spent linearly)\n";
  try {
    for (int j = 1; j <= looks; ++j) {
      const double t = std::min(j * opt.interval_s, opt.max_duration_s);
      auto idle_since = std::chrono::steady_clock::now();
      while (!reader || recorded_s(ws) < t * (1 - 1e-9)) {
        const std::string path = io::growing_snapshot(opt.recording, halves[generation % 2], &seen);
        if (!path.empty()) {
          ++generation;
          reader = std::make_unique<io::RecordingReader>(path, input);
          ws = carried_over(watched_channels(reader->info(), s), ws);
          idle_since = std::chrono::steady_clock::now();
          if (ws.empty()) {
            err << "allanlot: error: " << opt.recording << ": no channel matches a limit of "
                << opt.spec_path << "\n";
            return kExitUsage;
          }
        }
        if (reader && recorded_s(ws) >= t * (1 - 1e-9)) break;
        const double idle =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - idle_since).count();
        if (opt.replay || idle > opt.idle_timeout_s) {
          out << "recording ends at " << (reader ? recorded_s(ws) : 0.0)
              << " s; undecided: " << undecided(ws) << "\n";
          return kExitUndecided;
        }
        std::this_thread::sleep_for(std::chrono::duration<double>(opt.poll_s));
      }
      const double k = kernels::look_quantile(alpha, prev, t, opt.max_duration_s);
      out << "look " << j << " at " << t << " s (k = " << std::setprecision(4) << k << ")\n";
      look(*reader, ws, t, k, threads, out);
      out.flush();  // each look as it is made: the recording may run for hours
      prev = t;
      bool fail = false, open = false;
      for (const Watched& w : ws)
        for (const Limit& l : w.limits) {
          fail = fail || l.outcome == Outcome::Fail;
          open = open || l.outcome == Outcome::Undecided;
        }
      if (fail) {
        out << "unit fails at " << t << " s\n";
        return kExitSomeFailed;
      }
      if (!open) {
        out << "unit passes at " << t << " s\n";
        return kExitOk;
      }
    }
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  out << "undecided at " << opt.max_duration_s << " s: " << undecided(ws) << "\n";
  return kExitUndecided;
}

}  // namespace allanlot::workflow
