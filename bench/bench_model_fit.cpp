// Does the drawn fit follow the measured curve? For every channel of every results file in
// RESULTS_FOLDER whose recording lies in DATA_FOLDER (the five ADIS16405 units; their licence
// keeps them out of the repository, so both folders are arguments): the share of the fitted
// taus at which fit/adev_model lies within 3 half-widths of the measured overlapping Allan
// deviation, the half-width being that of its confidence interval on the model's side
// (dev_hi - dev above the measurement, dev - dev_lo below: allan/oadev's dev_lo, dev_hi, 68 %
// by default). The fitted taus: every oadev tau from fit/first_tau_fitted for an eq. (3) fit,
// every oadev tau for a poor fit that analyze modelled (the model describes the filter too).
//
//   bench_model_fit DATA_FOLDER RESULTS_FOLDER
//
// Prints a Markdown table, one line per channel (unit, channel, fit status, model, verdict of
// its terms' curve, taus, share within 3 half-widths, the taus beyond with the ratio of the
// drawn to the measured deviation) and the smallest share. Exit status 0,
// 2 for a wrong argument. Not a Google Benchmark.
#include "io/results.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace allanlot;

namespace {

struct Share {
  std::size_t within = 0, taus = 0;
  std::string missed;  // the taus beyond 3 half-widths: "tau (ratio model / measured)"
};

Share share_within(const io::ChannelResult& ch, const kernels::StatResult& oadev) {
  Share s;
  const io::FitRecord& f = *ch.fit;
  if (f.adev_model.size() != oadev.size()) return s;
  const double first = f.model.empty() && std::isfinite(f.first_tau_fitted) ? f.first_tau_fitted
                                                                            : oadev.tau_s.front();
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    if (oadev.tau_s[i] < first * (1.0 - 1e-12)) continue;
    const double d = oadev.dev[i], model = f.adev_model[i];
    const double half = model >= d ? oadev.dev_hi[i] - d : d - oadev.dev_lo[i];
    ++s.taus;
    if (std::abs(model - d) <= 3.0 * half) {
      ++s.within;
    } else {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%s%.3g (%.3f)", s.missed.empty() ? "" : ", ", oadev.tau_s[i],
                    model / d);
      s.missed += buf;
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || !fs::is_directory(argv[1]) || !fs::is_directory(argv[2])) {
    std::fprintf(stderr, "usage: %s DATA_FOLDER RESULTS_FOLDER (two folders)\n", argv[0]);
    return 2;
  }
  const fs::path data = fs::canonical(argv[1]);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(argv[2]))
    if (e.path().extension() == ".h5" && e.path().filename() != "lot_summary.h5")
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::printf(
      "| unit | channel | eq. (3) fit | model | within noise | taus | within 3 half-widths |\n"
      "|---|---|---|---|---|---|---|\n");
  double worst = 1.0;
  for (const fs::path& file : files) {
    const io::RecordingResult r = io::read_results(file);
    if (fs::path(r.source_file).parent_path() != data) continue;
    for (const io::ChannelResult& ch : r.channels) {
      const auto st = std::find_if(ch.stats.begin(), ch.stats.end(),
                                   [](const auto& s) { return s.first == "oadev"; });
      if (!ch.fit || st == ch.stats.end() || st->second.dev_lo.size() != st->second.size())
        continue;
      const Share s = share_within(ch, st->second);
      const double share = s.taus ? static_cast<double>(s.within) / static_cast<double>(s.taus) : 0;
      worst = std::min(worst, share);
      char chi[32];
      std::snprintf(chi, sizeof chi, "chi2/dof %.4g", ch.fit->chi2_dof);
      std::printf("| %s | %s | %s | %s | %s | %zu | %.0f %% | %s |\n", r.device_id.c_str(),
                  ch.path.c_str(), chi, ch.fit->model.empty() ? "-" : ch.fit->model.c_str(),
                  ch.fit->model_within_noise == 1   ? "yes"
                  : ch.fit->model_within_noise == 0 ? "no"
                                                    : "-",
                  s.taus, 100.0 * share, s.missed.c_str());
    }
  }
  std::printf("\nsmallest share: %.0f %%\n", 100.0 * worst);
  return 0;
}
