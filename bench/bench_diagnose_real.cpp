// The real-data study of docs/validation/2026-11-28-diagnose-real-sensors.md: every channel of
// every recording in a folder (the five ADIS16405 units; their licence keeps them out of the
// repository, so the folder is an argument), each diagnosed against its own eq. (3) fit, the
// corrected model re-diagnosed, and the eq. (3) fit repeated on the taus a named lowpass leaves
// alone.
//
//   bench_diagnose_real FOLDER [REPLICAS] [CHANNEL_SUBSTRING]   (REPLICAS: diagnose's default, 30)
//
// With BENCH_INJECT=1 it makes the injection table instead: into each channel's real samples
// a sinusoid, a Gauss-Markov process, a ramp and a step are added, one at a time, small (5
// sigma of the measured Allan variance where the effect's share is largest) and clear (20
// sigma), and the record is diagnosed against the corrected model of its untouched samples.
// BENCH_INJECT=ramp (any text but 1) keeps the injections whose name contains the text.
// BENCH_INJECT_SIZE=witness sizes a ramp and a step by their time-domain witnesses instead:
// the ramp's slope 5 and 20 times its sd under the corrected model (find_trend's z), the step
// 5 and 20 times the rms of the witness's differences of adjacent means at its best scale
// (find_step's statistic), which the Allan variance's sigma at the longest taus undersizes;
// the sinusoid and the Gauss-Markov process, which have no time-domain witness, stay sized by
// the Allan variance.
// BENCH_INJECT_SIGMAS=5,7,10,20 sets the sizes (default 5,20) for a sweep: then every size of an
// injection scales one draw, so that a larger size differs from a smaller one only in size.
// BENCH_INJECT_OWN=1 also diagnoses each injected record against its own eq. (3) fit, beside the
// corrected model of the untouched samples.
//
// Not a Google Benchmark: a table on stdout, one line per channel.
#include "io/recording.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/diagnose/lot_noise.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/simulate/lowpass.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace {

using namespace allanlot;

// The eq. (3) fit of the rows of `oadev` from averaging factor first_m on.
kernels::FitResult eq3(const kernels::StatResult& oadev, double rate_hz, std::int64_t n,
                       std::int64_t first_m) {
  const kernels::StatResult rows = kernels::fit_subset(oadev, first_m);
  kernels::Eq3Fit fit(rows.size());
  return fit.fit(rows, 1.0 / rate_hz, n);
}

// A record's overlapping Allan deviation (log grid, with its confidence) and its eq. (3) fit on
// every tau, as the model `spec`.
struct OwnFit {
  kernels::StatResult oadev;
  kernels::FitResult all;
  kernels::ChannelSpec spec;
};

OwnFit own_fit(std::span<const double> y, double rate) {
  const auto n = static_cast<std::int64_t>(y.size());
  const kernels::PhaseData ph = kernels::phase_from_rate(y, rate, 0);
  kernels::TauGridSpec grid;
  OwnFit f;
  f.oadev = kernels::compute(
      kernels::Stat::Oadev, ph,
      kernels::make_m_list(grid, kernels::max_m(kernels::Stat::Oadev, ph.n_points())), 0);
  kernels::add_confidence(kernels::Stat::Oadev, ph, f.oadev, kernels::kDefaultConfidence, 0);
  f.all = eq3(f.oadev, rate, n, 1);
  f.spec.rate_hz = rate;
  for (const kernels::Term t : kernels::all_terms())
    kernels::coefficient(f.spec.terms, t) = f.all.terms[static_cast<std::size_t>(t)].value;
  return f;
}

std::string names(const kernels::Diagnosis& d) {
  std::string s;
  for (std::size_t i = 0; i < d.effects_named.size(); ++i) {
    if (!s.empty()) s += ',';
    s += kernels::effect_name(d.effects_named[i]);
    std::string args;
    for (const auto& p : d.effect_parameters[i])
      if (p.name == "cutoff_hz" || p.name == "taps" || p.name == "tau_c_s" || p.name == "q" ||
          p.name == "spread_hz" ||
          (p.name == "frequency_hz" && d.effects_named[i] == kernels::Effect::Resonance))
        args += (args.empty() ? "" : " ") + p.name +
                (p.bound < 0   ? "<"
                 : p.bound > 0 ? ">"
                               : "=") +
                std::to_string(p.value).substr(0, 6);
    if (!args.empty()) s += "(" + args + ")";
  }
  return s.empty() ? "-" : s;
}

// Each round's choice and its candidates' criteria (BENCH_VERBOSE), with their notes
// (BENCH_NOTES).
void print_rounds(const kernels::Diagnosis& d) {
  for (const auto& it : d.iterations) {
    std::printf("    round: %s, gap %.3g ->%.3g; criteria:",
                std::string(kernels::effect_name(it.effect)).c_str(), it.gap_before, it.gap_after);
    for (const auto& c : it.candidates)
      if (c.evaluated)
        std::printf(" %s %+.1f", std::string(kernels::effect_name(c.effect)).c_str(), c.delta_ic);
    std::printf("\n");
    if (std::getenv("BENCH_NOTES"))
      for (const auto& c : it.candidates)
        if (!c.note.empty())
          std::printf("      %s: %s\n", std::string(kernels::effect_name(c.effect)).c_str(),
                      c.note.c_str());
  }
}

// One injected effect of unit size: a spec holding only it.
struct Injection {
  const char* name;
  kernels::Effect effect;
  kernels::ChannelSpec unit;
};

std::vector<Injection> injections(double rate_hz, double duration_s) {
  kernels::ChannelSpec base;
  base.rate_hz = rate_hz;
  std::vector<Injection> out;
  // A line at 0.37 Hz (no ADIS16405 line is near it), a hump at tau_c = 2 s, a ramp, and a jump
  // at 0.37 of the record.
  auto sin = base;
  sin.sinusoids.push_back({1.0, 0.37, 0.4});
  out.push_back({"sinusoid 0.37 Hz", kernels::Effect::Sinusoid, sin});
  auto gm = base;
  gm.markovs.push_back({1.0, 2.0});
  out.push_back({"markov tau_c 2 s", kernels::Effect::Markov, gm});
  auto ramp = base;
  ramp.terms.R = 1.0;
  out.push_back({"ramp", kernels::Effect::Ramp, ramp});
  auto step = base;
  step.steps.push_back({1.0, 0.37 * duration_s});
  out.push_back({"step", kernels::Effect::Step, step});
  return out;
}

// The amplitude at which `unit`'s Allan variance is `sigmas` standard deviations of the measured
// variance (avar sqrt(2 / edf), the chi-square's) at the tau where its share is largest.
double amplitude_for(const kernels::ChannelSpec& unit, const kernels::Diagnosis& d, std::int64_t n,
                     double sigmas) {
  double most = 0.0;
  for (std::size_t i = 0; i < d.m.size(); ++i) {
    const double sd = d.avar_measured[i] * std::sqrt(2.0 / d.edf_after[i]);
    most = std::max(most, kernels::model_avar_sampled(unit, d.m[i], n) / sd);
  }
  return std::sqrt(sigmas / most);
}

// The size at which a ramp or a step is `sigmas` standard deviations of its time-domain witness
// under the corrected model: the slope's sd `slope_sd` (trend_slope_variance) for a ramp; for a
// step, the rms of the differences of adjacent m-sample means, sqrt(2 avar(m)) (NIST SP1065 eq.
// (11)), at its smallest over the witness's scales m = 1, 2, 4, ... while the record holds 16
// pairs of means (find_step.cpp), where a jump stands out most.
double witness_size(const Injection& inj, const kernels::Diagnosis& d, std::int64_t n,
                    double slope_sd, double sigmas) {
  if (inj.effect == kernels::Effect::Ramp) return sigmas * slope_sd;
  kernels::ChannelSpec model = d.model_after;
  model.steps.clear();
  double least = std::numeric_limits<double>::infinity();
  for (std::int64_t m = 1; (n - 2 * m + 1) / (2 * m) >= 16; m *= 2)
    least = std::min(least, 2.0 * kernels::model_avar_sampled(model, m, n));
  return sigmas * std::sqrt(least);
}

// The sizes of BENCH_INJECT_SIGMAS, "5,7,10,20"; a bad list ends the bench.
std::vector<double> parse_sizes(const char* text) {
  std::vector<double> out;
  const std::string s(text);
  for (std::size_t at = 0; at <= s.size();) {
    const std::size_t comma = std::min(s.find(',', at), s.size());
    char* end = nullptr;
    const std::string item = s.substr(at, comma - at);
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !(v > 0.0) || !std::isfinite(v)) {
      std::fprintf(stderr, "BENCH_INJECT_SIGMAS: '%s' is not a positive number\n", item.c_str());
      std::exit(2);
    }
    out.push_back(v);
    at = comma + 1;
  }
  return out;
}

kernels::ChannelSpec scaled(kernels::ChannelSpec s, double a) {
  s.terms.R *= a;
  for (auto& x : s.sinusoids)
    x.amplitude *= a;
  for (auto& x : s.markovs)
    x.sigma *= a;
  for (auto& x : s.steps)
    x.size *= a;
  return s;
}

// The injection rows of one channel: each effect, small and clear, added to the real samples
// and diagnosed against the corrected model of the untouched record (`d.model_after`).
void inject_rows(const std::string& unit, const std::string& channel,
                 const kernels::LargeVector<double>& y, double rate, const kernels::Diagnosis& d,
                 const kernels::DiagnoseOptions& opt) {
  const auto n = static_cast<std::int64_t>(y.size());
  // The sd of the record's slope under the corrected model (find_trend's yardstick).
  const double slope_sd =
      std::sqrt(kernels::trend_slope_variance(d.model_after, static_cast<double>(n) / rate));
  std::vector<double> add(y.size()), z(y.size());
  const char* sweep = std::getenv("BENCH_INJECT_SIGMAS");
  const std::vector<double> sizes = sweep != nullptr ? parse_sizes(sweep) : std::vector{5.0, 20.0};
  const char* only = std::getenv("BENCH_INJECT");
  const bool all = only == nullptr || std::string(only) == "1";
  const char* size_by = std::getenv("BENCH_INJECT_SIZE");
  const bool witness = size_by != nullptr && std::string(size_by) == "witness";
  const std::vector<Injection> list = injections(rate, static_cast<double>(n) / rate);
  for (std::size_t k = 0; k < list.size(); ++k)
    for (std::size_t j = 0; j < sizes.size(); ++j) {
      const Injection& inj = list[k];
      const double sigmas = sizes[j];
      // Two streams per injection, from its place in the list, so that one kept alone draws what
      // it draws beside the others; a sweep scales the first.
      const std::uint64_t this_stream = 2 * k + (sweep != nullptr ? 0 : j);
      if (!all && std::string(inj.name).find(only) == std::string::npos) continue;
      const bool by_witness =
          witness && (inj.effect == kernels::Effect::Ramp || inj.effect == kernels::Effect::Step);
      const double a = by_witness ? witness_size(inj, d, n, slope_sd, sigmas)
                                  : amplitude_for(inj.unit, d, n, sigmas);
      kernels::simulate_channel(scaled(inj.unit, a), 4242, this_stream, add, 0);
      for (std::size_t i = 0; i < y.size(); ++i)
        z[i] = y[i] + add[i];
      const kernels::Diagnosis g = kernels::diagnose(z, rate, d.model_after, opt);
      // BENCH_INJECT_OWN: the same record diagnosed against its own eq. (3) fit as well.
      std::string against_own;
      if (std::getenv("BENCH_INJECT_OWN"))
        against_own = "; against its own eq. (3) fit: " +
                      names(kernels::diagnose(z, rate, own_fit(z, rate).spec, opt));
      const bool named = std::find(g.effects_named.begin(), g.effects_named.end(), inj.effect) !=
                         g.effects_named.end();
      const bool exact = named && g.effects_named.size() == 1;
      // A model that has a ramp already can only find its R wrong, not name a second ramp.
      const bool has_ramp = inj.effect == kernels::Effect::Ramp && d.model_after.terms.R > 0.0;
      // What the time-domain witnesses see of a ramp or a step: the slope's z under the
      // corrected model (the injected slope over its sd, and the record's slope, z, as measured)
      // and the largest jump's statistic (rms of the differences of adjacent means), time and p.
      char seen[96] = "";
      if (inj.effect == kernels::Effect::Ramp)
        std::snprintf(seen, sizeof seen, "; slope z %.2g injected, %.2g measured", a / slope_sd,
                      g.trend.z);
      if (inj.effect == kernels::Effect::Step)
        std::snprintf(seen, sizeof seen, "; largest jump %.2g rms at %.0f s, p %.2g",
                      g.step.statistic, g.step.time_s, g.step.p_value);
      std::printf(
          "| %s | %s | %s | %.3g sigma (%.3g%s) | %s%s | %s | %.3g (%.3g) |\n", unit.c_str(),
          channel.c_str(), inj.name, sigmas, a, seen, names(g).c_str(), against_own.c_str(),
          exact      ? "exact"
          : named    ? "named, with others"
          : has_ramp ? (g.coefficients_wrong ? "model's ramp found wrong" : "model has a ramp")
                     : "missed",
          g.after.gap, g.mc_after.gap_p95);
      if (std::getenv("BENCH_VERBOSE")) {
        for (const auto& note : g.notes)
          std::printf("    note: %s\n", note.c_str());
        print_rounds(g);
      }
      std::fflush(stdout);
    }
}

// Whether the lot of channels is within noise as a whole (kernels/diagnose/lot_noise.hpp): how
// many channels are beyond their replicas' p95, against the chance of that many when every
// corrected model is complete.
struct LotTally {
  int channels = 0, beyond = 0;
  std::string beyond_list;
  void add(const std::string& name, const kernels::Diagnosis& d) {
    ++channels;
    if (d.gap_within_noise) return;
    ++beyond;
    // The channel's Monte Carlo p-value: the share of its replicas' gaps at or above its own.
    const auto& g = d.mc_after.gaps;
    const auto at_or_above =
        std::count_if(g.begin(), g.end(), [&](double x) { return x >= d.after.gap; });
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%s %.3g (p95 %.3g, p %.2g)", beyond_list.empty() ? "" : "; ",
                  name.c_str(), d.after.gap, d.mc_after.gap_p95,
                  static_cast<double>(1 + at_or_above) / static_cast<double>(g.size() + 1));
    beyond_list += buf;
  }
  void print(int replicas) const {
    if (channels == 0 || replicas < 1) return;
    const double q = kernels::beyond_p95_probability(replicas);
    const std::vector<double> each(static_cast<std::size_t>(channels), q);
    std::printf("\nWithin noise: %d of %d channels. Beyond their replicas' p95: %d (%s).\n"
                "A complete model is beyond the p95 of %d replicas with probability %.3f: %.2g of "
                "%d expected, %d or more with probability %.2g.\n",
                channels - beyond, channels, beyond, beyond_list.c_str(), replicas, q, q * channels,
                channels, beyond, kernels::at_least_probability(each, beyond));
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::filesystem::is_directory(argv[1])) {
    std::fprintf(stderr, "usage: %s FOLDER [REPLICAS] [CHANNEL_SUBSTRING]\n", argv[0]);
    if (argc >= 2) std::fprintf(stderr, "%s: %s is not a folder\n", argv[0], argv[1]);
    return 2;
  }
  const int replicas = argc > 2 ? std::atoi(argv[2]) : kernels::DiagnoseOptions{}.mc_replicas;
  const std::string only = argc > 3 ? argv[3] : "";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(argv[1]))
    if (e.path().extension() == ".h5") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  const bool inject = std::getenv("BENCH_INJECT") != nullptr;
  if (inject)
    std::printf("| unit | channel | injected | size (amplitude) | named against the corrected "
                "model | verdict | gap after (replica p95) |\n|---|---|---|---|---|---|---|\n");
  else
    std::printf(
        "| unit | channel | chi2/dof all taus | named against own fit | gap before -> after "
        "(replica p95) | first m | chi2/dof from first m | fixed model re-diagnosed | "
        "largest jump (rms, p) |\n"
        "|---|---|---|---|---|---|---|---|---|\n");
  const char* only_unit = std::getenv("BENCH_UNIT");
  LotTally lot;
  for (const auto& file : files) {
    if (only_unit != nullptr && file.stem().string().find(only_unit) == std::string::npos) continue;
    const io::RecordingReader reader(file.string());
    for (const auto& ch : reader.info().channels) {
      if (!only.empty() && ch.path.find(only) == std::string::npos) continue;
      const kernels::LargeVector<double> y = reader.read(ch);
      const double rate = ch.sample_rate_hz;
      const auto n = static_cast<std::int64_t>(y.size());
      const OwnFit own = own_fit(y, rate);
      kernels::DiagnoseOptions opt;
      opt.mc_replicas = replicas;
      const kernels::Diagnosis d = kernels::diagnose(y, rate, own.spec, opt);
      if (inject) {
        inject_rows(file.stem().string(), ch.path, y, rate, d, opt);
        continue;
      }
      const std::int64_t first = kernels::lowpass_first_m(d.model_after.lowpass, rate, n);
      const kernels::FitResult cut = eq3(own.oadev, rate, n, first);
      const kernels::Diagnosis again = kernels::diagnose(y, rate, d.model_after, opt);
      lot.add(file.stem().string() + " " + ch.path, d);
      std::printf("| %s | %s | %.4g | %s | %.3g -> %.3g (%.3g) | %lld | %.4g | %s, gap %.3g | "
                  "%.3g at %.1f s (%.2g, %.2g) |\n",
                  file.stem().string().c_str(), ch.path.c_str(), own.all.chi2_dof, names(d).c_str(),
                  d.before.gap, d.after.gap, d.mc_after.gap_p95, static_cast<long long>(first),
                  cut.chi2_dof, names(again).c_str(), again.after.gap, d.step.size, d.step.time_s,
                  d.step.statistic, d.step.p_value);
      if (std::getenv("BENCH_VERBOSE")) {
        for (const auto& note : d.notes)
          std::printf("    note: %s\n", note.c_str());
        const auto& t = d.model_after.terms;
        std::printf("    model after: R %.3g K %.3g B %.3g N %.3g Q %.3g", t.R, t.K, t.B, t.N, t.Q);
        for (const auto& g : d.model_after.markovs)
          std::printf("; markov %.3g %.4g s", g.sigma, g.tau_c_s);
        for (const auto& r : d.model_after.resonances)
          std::printf("; resonance %.3g %.4g Hz q %.4g", r.sigma, r.frequency_hz, r.q);
        std::printf("\n");
        print_rounds(d);
        for (std::size_t i = 0; i < d.tau_s.size(); ++i)
          std::printf("    tau %.4g  meas/before %.4f  meas/after %.4f  z_after %.2f  edf %.4g\n",
                      d.tau_s[i], d.avar_measured[i] / d.before.avar_model[i],
                      d.avar_measured[i] / d.after.avar_model[i], d.after.z[i], d.edf_after[i]);
      }
      std::fflush(stdout);
    }
  }
  if (!inject) lot.print(replicas);
  return 0;
}
