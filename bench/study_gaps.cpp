// The gap study of docs/validation/2026-11-28-gaps.md: into every channel of every recording in
// a folder (the five ADIS16405 units; their licence keeps them out of the repository, so the
// folder is an argument) drops are injected, 1 to 1000 runs of missing samples, and the
// overlapping Allan deviation of the dropped record, under the default gap policy and under
// `skip`, is compared with that of the same record without drops.
//
//   study_gaps FOLDER [DROPS] [POLICY] [MAXLEN]   (DROPS: comma list, default 1,12,100,1000;
//     POLICY: the policy studied, default fill:10; MAXLEN: longest drop, default 5;
//     STUDY_NO_PIPELINE=1 leaves out the end-to-end part)
//
// Per unit, channel and drop count: the share of the gap-free taus where the gap-free OADEV lies
// inside the gapped run's interval (a tau the gapped run lacks counts as outside), the worst
// distance of the gap-free OADEV from the gapped estimate in half-widths of the interval (the
// half on its side) over the taus both have, the ratio of the largest taus, and whether TOTDEV
// runs. Then the user's case end to end (src/pipeline, as `analyze` runs a channel: OADEV and
// TOTDEV, the eq. (3) fit, no PSD): a dozen drops in each gyro channel, the OADEV row nearest
// 649 s with its n, the largest tau and the bias-instability read-out, gap-free, under the
// policy and under skip. Drops: positions
// uniform over the record, lengths 1 (60 %) or 2 to MAXLEN samples (a logger's dropped rows);
// seeded by unit, channel and count, so that every run of the study draws the same drops.
//
// Not a Google Benchmark: a table on stdout, one line per channel and count, then the
// worst case per count.
#include "io/recording.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "src/pipeline/channel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace allanlot;
namespace fs = std::filesystem;

struct Outcome {
  double inside = 0;     // share of taus inside
  double worst = 0;      // half-widths
  double worst_tau = 0;  // s, where it is reached
  double tau_ratio = 0;  // largest tau, dropped / gap-free
  bool totdev = false;   // TOTDEV runs
  std::int64_t filled = 0;
};

std::size_t g_max_len = 5;  // longest drop, samples (MAXLEN)

std::vector<double> with_drops(const std::vector<double>& y, int drops, unsigned seed) {
  std::vector<double> out = y;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> at(0, y.size() - g_max_len - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> longer(2, std::max<std::size_t>(g_max_len, 2));
  for (int d = 0; d < drops; ++d) {
    const std::size_t a = at(rng);
    const std::size_t len = u(rng) < 0.6 ? 1 : longer(rng);
    for (std::size_t k = a; k < a + len; ++k)
      out[k] = std::nan("");
  }
  return out;
}

kernels::StatResult oadev(const kernels::PhaseData& p) {
  const auto ms =
      kernels::stat_m_list(kernels::TauGridSpec{}, kernels::Stat::Oadev,
                           kernels::max_m(kernels::Stat::Oadev, p.n_points()), p.n_points());
  kernels::StatResult r = kernels::compute(kernels::Stat::Oadev, p, ms, 1);
  kernels::add_confidence(kernels::Stat::Oadev, p, r, kernels::kDefaultConfidence, 1);
  return r;
}

Outcome compare(const kernels::StatResult& clean, const std::vector<double>& dropped,
                kernels::DataType type, double rate_hz, const kernels::GapPolicy& policy) {
  std::vector<double> y = dropped;
  kernels::GapFill fill;
  const kernels::PhaseData p = kernels::make_phase(y, type, rate_hz, policy, &fill, 1);
  const kernels::StatResult g = oadev(p);
  Outcome o;
  o.filled = fill.filled;
  std::map<std::int64_t, std::size_t> row;
  for (std::size_t i = 0; i < g.size(); ++i)
    row[g.m[i]] = i;
  std::size_t inside = 0;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const auto it = row.find(clean.m[i]);
    if (it == row.end()) continue;  // outside; the tau ratio says how many are lost
    const std::size_t j = it->second;
    const double d0 = clean.dev[i], d = g.dev[j];
    inside += (d0 >= g.dev_lo[j] && d0 <= g.dev_hi[j]) ? 1 : 0;
    const double half = d0 >= d ? g.dev_hi[j] - d : d - g.dev_lo[j];
    if (std::abs(d0 - d) / half > o.worst) {
      o.worst = std::abs(d0 - d) / half;
      o.worst_tau = clean.tau_s[i];
    }
  }
  o.inside = static_cast<double>(inside) / static_cast<double>(clean.size());
  o.tau_ratio = g.size() ? g.tau_s.back() / clean.tau_s.back() : 0.0;
  o.totdev = !p.has_gaps();
  return o;
}

std::vector<int> parse_counts(const char* text) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    out.push_back(std::stoi(item));
  return out;
}

struct Worst {
  double inside = 1, worst = 0, tau_ratio = 1;
  int totdev = 0, channels = 0;
  void add(const Outcome& o) {
    inside = std::min(inside, o.inside);
    worst = std::max(worst, o.worst);
    tau_ratio = std::min(tau_ratio, o.tau_ratio);
    totdev += o.totdev ? 1 : 0;
    ++channels;
  }
};

// One channel as `analyze --stats oadev,totdev --no-psd --gaps POLICY` computes it.
io::ChannelResult pipeline_run(const io::ChannelInfo& ch, const std::vector<double>& y,
                               const kernels::GapPolicy& policy) {
  pipeline::ChannelOptions opt;
  opt.stats = {kernels::Stat::Oadev, kernels::Stat::Totdev};
  opt.psd = false;
  opt.gaps = policy;
  kernels::LargeVector<double> samples(y.begin(), y.end());
  return pipeline::analyze_channel(ch, std::move(samples), opt).result;
}

void print_case(const char* label, const io::ChannelResult& r) {
  const kernels::StatResult* o = nullptr;
  bool totdev = false;
  for (const auto& [name, st] : r.stats) {
    if (name == "oadev") o = &st;
    totdev = totdev || name == "totdev";
  }
  double bi = NAN;
  if (r.fit)
    for (const io::ReadoutRecord& x : r.fit->readouts)
      if (x.name == "bias_instability") bi = x.value_datasheet;
  if (!o || o->size() == 0) {
    std::printf("  %-8s no oadev\n", label);
    return;
  }
  std::size_t k = 0;
  for (std::size_t i = 0; i < o->size(); ++i)
    if (std::abs(std::log(o->tau_s[i] / 649.0)) < std::abs(std::log(o->tau_s[k] / 649.0))) k = i;
  std::printf("  %-8s tau %7.1f s: oadev %.5f [%.5f, %.5f] n %7lld | largest tau %6.0f s | "
              "bias instability %6.2f deg/h | totdev %s\n",
              label, o->tau_s[k], o->dev[k], o->dev_lo[k], o->dev_hi[k],
              static_cast<long long>(o->n[k]), o->tau_s.back(), bi, totdev ? "yes" : "no");
}

void user_case(const std::vector<fs::path>& files, const kernels::GapPolicy& policy) {
  std::printf("\nthe user's case: 12 drops in each gyro channel, through the pipeline\n");
  unsigned seed = 9001;
  for (const fs::path& file : files) {
    io::RecordingReader reader(file.string());
    for (const io::ChannelInfo& ch : reader.info().channels) {
      if (ch.path.find("gyro") == std::string::npos) continue;
      const kernels::LargeVector<double> raw = reader.read(ch);
      const std::vector<double> y(raw.begin(), raw.end());
      const std::vector<double> dropped = with_drops(y, 12, seed++);
      std::printf("%s %s\n", reader.info().device_id.c_str(), ch.path.c_str());
      print_case("gap-free", pipeline_run(ch, y, policy));
      print_case(kernels::to_string(policy).c_str(), pipeline_run(ch, dropped, policy));
      print_case("skip", pipeline_run(ch, dropped, kernels::parse_gap_policy("skip")));
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: study_gaps FOLDER [DROPS] [POLICY]\n");
    return 2;
  }
  const std::vector<int> counts = parse_counts(argc > 2 ? argv[2] : "1,12,100,1000");
  const kernels::GapPolicy policy =
      kernels::parse_gap_policy(argc > 3 ? argv[3] : kernels::to_string(kernels::GapPolicy{}));
  const kernels::GapPolicy skip = kernels::parse_gap_policy("skip");
  if (argc > 4) g_max_len = static_cast<std::size_t>(std::stoul(argv[4]));
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(argv[1]))
    if (e.path().extension() == ".h5") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::map<int, Worst> worst_fill, worst_skip;
  std::printf("%-14s %-12s %5s %7s | %-8s %7s %7s %8s %6s | %-8s %7s %7s %8s %6s\n", "unit",
              "channel", "drops", "filled", policy == kernels::GapPolicy{} ? "default" : "policy",
              "inside", "worst", "at (s)", "tau", "skip", "inside", "worst", "at (s)", "tau");
  unsigned seed = 1;
  for (const fs::path& file : files) {
    io::RecordingReader reader(file.string());
    for (const io::ChannelInfo& ch : reader.info().channels) {
      const kernels::LargeVector<double> raw = reader.read(ch);
      const std::vector<double> y(raw.begin(), raw.end());
      const kernels::StatResult clean =
          oadev(kernels::make_phase(y, ch.data_type, ch.sample_rate_hz, 1));
      for (const int drops : counts) {
        const std::vector<double> dropped = with_drops(y, drops, seed++);
        const Outcome f = compare(clean, dropped, ch.data_type, ch.sample_rate_hz, policy);
        const Outcome s = compare(clean, dropped, ch.data_type, ch.sample_rate_hz, skip);
        worst_fill[drops].add(f);
        worst_skip[drops].add(s);
        std::printf("%-14s %-12s %5d %7lld | %8s %7.3f %7.2f %8.2f %6.3f | %8s %7.3f %7.2f %8.2f "
                    "%6.3f\n",
                    reader.info().device_id.c_str(), ch.path.c_str(), drops,
                    static_cast<long long>(f.filled), f.totdev ? "totdev" : "-", f.inside, f.worst,
                    f.worst_tau, f.tau_ratio, s.totdev ? "totdev" : "-", s.inside, s.worst,
                    s.worst_tau, s.tau_ratio);
        std::fflush(stdout);
      }
    }
  }
  std::printf("\nworst case over the channels, per drop count (policy %s | skip)\n",
              kernels::to_string(policy).c_str());
  std::printf("%5s | %8s %8s %8s %8s | %8s %8s %8s %8s\n", "drops", "inside", "worst", "tau",
              "totdev", "inside", "worst", "tau", "totdev");
  for (const int drops : counts) {
    const Worst& f = worst_fill[drops];
    const Worst& s = worst_skip[drops];
    std::printf("%5d | %8.3f %8.2f %8.3f %5d/%-2d | %8.3f %8.2f %8.3f %5d/%-2d\n", drops, f.inside,
                f.worst, f.tau_ratio, f.totdev, f.channels, s.inside, s.worst, s.tau_ratio,
                s.totdev, s.channels);
  }
  if (!std::getenv("STUDY_NO_PIPELINE")) user_case(files, policy);
  return 0;
}
