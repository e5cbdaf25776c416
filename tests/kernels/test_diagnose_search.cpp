// kernels/diagnose's tau_c search: it spans one sample to the record's
// length, and a tau_c at either end is reported as a limit with no sigma; inside, it is an
// estimate with one. Exact model curves (no noise), so that where the search ends is known.
#include "kernels/diagnose/internal.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using namespace kernels::diagnose_detail;

constexpr double kRate = 100.0;
constexpr std::int64_t kSamples = 60000;

// The curve of `truth` itself on a log grid of 8 per decade, with the edf of that model.
Curve exact_curve(const kernels::ChannelSpec& truth, Bases& b) {
  Curve cv;
  cv.tau0 = 1.0 / kRate;
  cv.n_samples = kSamples;
  for (double m = 1.0; m <= static_cast<double>(kSamples) / 4.0; m *= std::pow(10.0, 0.125)) {
    const auto mi = static_cast<std::int64_t>(std::llround(m));
    if (!cv.m.empty() && cv.m.back() == mi) continue;
    cv.m.push_back(mi);
    cv.tau.push_back(static_cast<double>(mi) * cv.tau0);
    cv.y.push_back(kernels::model_avar_sampled(truth, mi));
  }
  prepare_edf(cv);
  b = make_bases(cv, kRate);
  use_edf(cv, model_edf(truth, cv, b));
  return cv;
}

kernels::ChannelSpec white() {
  kernels::ChannelSpec s;
  s.rate_hz = kRate;
  s.terms.N = 0.01;
  return s;
}

// The white noise given and fixed, a Gauss-Markov effect searched.
Fit search(const Curve& cv, const Bases& b) {
  std::vector<Component> comps = components_of(white());
  comps.push_back(searched_component(kernels::GaussMarkov{}));
  return search_tau_c(comps, comps.size() - 1, cv, b);
}

std::vector<kernels::Parameter> markov_parameters(const Fit& f, const Curve& cv, const Bases& b) {
  return parameters_of(f.comps.back(), fill_sigmas(f, cv, b, 8.0), f.comps.size() - 1);
}

TEST(DiagnoseSearch, TauCInsideTheRangeIsAnEstimate) {
  auto truth = white();
  truth.markovs.push_back({0.02, 1.0});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  const Fit f = search(cv, b);
  // Not exact: the fit works on ln avar less the log-chi-square bias -(psi(edf/2) - ln(edf/2)),
  // about 1/edf, which an exact curve does not have; a few per cent at the hump's few-edf taus.
  EXPECT_NEAR(as<kernels::GaussMarkov>(f.comps.back()).tau_c_s, 1.0, 0.05);
  const auto ps = markov_parameters(f, cv, b);
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps[1].bound, 0);
  EXPECT_TRUE(std::isfinite(ps[1].sigma));
}

TEST(DiagnoseSearch, TauCBeyondTheRecordIsALowerLimit) {
  // tau_c = 1e5 s over a 600 s record: a random walk K^2 = 2 sigma^2 / tau_c at every tau, which
  // any tau_c beyond the record fits about as well; the search ends at the record's length.
  auto truth = white();
  truth.markovs.push_back({std::sqrt(0.5 * 4e-6 * 1e5), 1e5});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  const Fit f = search(cv, b);
  EXPECT_LE(as<kernels::GaussMarkov>(f.comps.back()).tau_c_s,
            static_cast<double>(kSamples) / kRate * (1.0 + 1e-12));
  EXPECT_GT(as<kernels::GaussMarkov>(f.comps.back()).tau_c_s,
            0.9 * static_cast<double>(kSamples) / kRate);
  const auto ps = markov_parameters(f, cv, b);
  EXPECT_EQ(ps[1].bound, 1);
  EXPECT_TRUE(std::isnan(ps[1].sigma));
}

TEST(DiagnoseSearch, TauCBelowOneSampleIsAnUpperLimit) {
  // tau_c = 1 ms at tau0 = 10 ms: white noise N^2 = 2 sigma^2 tau_c at every tau; the search
  // ends at one sample.
  auto truth = white();
  truth.markovs.push_back({0.5, 1e-3});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  const Fit f = search(cv, b);
  EXPECT_GE(as<kernels::GaussMarkov>(f.comps.back()).tau_c_s, (1.0 - 1e-12) / kRate);
  EXPECT_LT(as<kernels::GaussMarkov>(f.comps.back()).tau_c_s, 1.1 / kRate);
  const auto ps = markov_parameters(f, cv, b);
  EXPECT_EQ(ps[1].bound, -1);
  EXPECT_TRUE(std::isnan(ps[1].sigma));
}

// A resonance like the ADIS16405 z gyroscopes' (docs/diagnose.md "Real sensors"), under their
// filter, beside white noise: the search finds its frequency and size from the exact curve, and
// a q that the curve resolves (about 20 coherence times inside the taus) is an estimate.
TEST(DiagnoseSearch, ResonanceFrequencyAndSizeAreFound) {
  for (const double q : {8.0, 40.0}) {
    auto truth = white();
    truth.terms.N = 0.04;
    truth.lowpass.cutoff_hz = 28.0;
    truth.resonances.push_back({0.24, 20.0, q});
    Bases b;
    const Curve cv = exact_curve(truth, b);
    auto given = truth;
    given.resonances.clear();
    std::vector<Component> comps = components_of(given);
    comps.push_back(searched_component(kernels::Resonance{}));
    const Fit f = search_resonance(comps, comps.size() - 1, cv, b, true);
    const Component& got = f.comps.back();
    const auto& res = as<kernels::Resonance>(got);
    EXPECT_NEAR(res.frequency_hz / 20.0, 1.0, 2e-3) << "q " << q;
    EXPECT_NEAR(res.sigma / 0.24, 1.0, 0.05) << "q " << q;
    EXPECT_NEAR(std::log(res.q / q), 0.0, std::log(1.3)) << "q " << q;
    EXPECT_EQ(got.nl_bound, 0);
    EXPECT_EQ(got.q_bound, 0);
    const auto p = parameters_of(got, fill_sigmas(f, cv, b, 8.0), comps.size() - 1);
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[2].name, "q");
    EXPECT_TRUE(std::isfinite(p[1].sigma) && std::isfinite(p[2].sigma));
  }
}

// A resonance whose ripples outlast every tau is a line to the curve: its q ends at the top of
// the range, reported as a lower limit with no sigma, and the model stays a valid spec (the
// range's end, exp(log(1e5)), must not round past what simulate accepts).
TEST(DiagnoseSearch, ResonanceAsNarrowAsALineIsALowerLimitOfQ) {
  auto truth = white();
  truth.resonances.push_back({0.02, 5.0, kernels::kResonanceMaxQ});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  std::vector<Component> comps = components_of(white());
  comps.push_back(searched_component(kernels::Resonance{}));
  const Fit f = search_resonance(comps, comps.size() - 1, cv, b, true);
  EXPECT_NEAR(as<kernels::Resonance>(f.comps.back()).frequency_hz / 5.0, 1.0, 2e-3);
  EXPECT_EQ(f.comps.back().q_bound, 1);
  const auto p = parameters_of(f.comps.back(), fill_sigmas(f, cv, b, 8.0), comps.size() - 1);
  EXPECT_EQ(p[2].bound, 1);
  EXPECT_TRUE(std::isnan(p[2].sigma));
  EXPECT_NO_THROW(kernels::validate(spec_of(f.comps, white())));
}

// The ADIS16405 x and y gyroscopes' filter is a 2-tap boxcar (lag-1 autocorrelation 0.17 to
// 0.29, none beyond): each form's best grid point is refined before the forms are compared, so
// the boxcar is found, not the one-pole filter whose grid point happened to lie nearer its own
// optimum (which would come with a broad resonance beside it on those gyroscopes).
TEST(DiagnoseSearch, TwoTapBoxcarIsFoundAsABoxcar) {
  for (const double taps : {1.17, 1.21, 1.33}) {
    auto truth = white();
    truth.terms.N = 0.04;
    truth.lowpass.taps = taps;
    Bases b;
    const Curve cv = exact_curve(truth, b);
    auto given = truth;
    given.lowpass = {};
    std::vector<Component> comps = components_of(given);
    for (Component& c : comps)
      c.free = true;
    comps.push_back(component(kernels::Lowpass{}));
    comps.back().pinned = true;
    const Fit f = search_lowpass(comps, comps.size() - 1, cv, b);
    EXPECT_EQ(as<kernels::Lowpass>(f.comps.back()).cutoff_hz, 0.0) << "taps " << taps;
    EXPECT_NEAR(as<kernels::Lowpass>(f.comps.back()).taps, taps, 1e-3) << "taps " << taps;
    EXPECT_EQ(f.comps.back().nl_bound, 0);
  }
}

// A hump whose tau_c ends at one sample is no hump but a shape at the shortest taus, the
// sensor filter's: over white noise through a boxcar (the model given without it) the markov
// candidate is withdrawn with a note, and the filter's deficit is left to `lowpass` (an
// ADIS16405 z gyroscope named such a hump ahead of its filter).
TEST(DiagnoseSearch, HumpAtOneSampleIsNotAHump) {
  auto truth = white();
  truth.terms.N = 0.04;
  truth.lowpass.taps = 1.5;
  Bases b;
  const Curve cv = exact_curve(truth, b);
  auto given = truth;
  given.lowpass = {};
  std::vector<Component> comps = components_of(given);
  const Criterion crit{1.0, 0.005, 8.0, kRate};
  const Fit ref = fit_components(comps, cv, b);
  const CandidateFit cf =
      evaluate_candidate(kernels::Effect::Markov, comps, Witnesses{}, 0, ref.chi2, cv, b, crit);
  EXPECT_FALSE(cf.info.evaluated);
  EXPECT_NE(cf.info.note.find("one sample"), std::string::npos) << cf.info.note;
  const CandidateFit lp =
      evaluate_candidate(kernels::Effect::Lowpass, comps, Witnesses{}, 0, ref.chi2, cv, b, crit);
  EXPECT_TRUE(lp.info.evaluated);
  EXPECT_GT(lp.info.delta_ic, 0.0);
}

// A resonance the curve leaves at a bound of q is measured on the periodogram around its f0;
// where the periodogram shows no peak there, it is no narrowband process and the candidate is
// withdrawn with a note (the exact curve of a line-like resonance, against the periodogram of a
// record of white noise alone).
TEST(DiagnoseSearch, ResonanceAtABoundThePeriodogramDoesNotSeeIsWithdrawn) {
  auto truth = white();
  truth.resonances.push_back({0.02, 5.0, kernels::kResonanceMaxQ});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  std::vector<double> y(static_cast<std::size_t>(kSamples));
  kernels::simulate_channel(white(), 4, 0, y, 1);
  const kernels::PsdResult psd = full_periodogram(y, kRate, 1);
  Witnesses seen;
  seen.periodogram = &psd;
  const CandidateFit cf =
      resonance_candidate(components_of(white()), cv, b, seen, [](int k) { return 2.0 * k; });
  EXPECT_TRUE(cf.fit.comps.empty());
  EXPECT_NE(cf.info.note.find("no peak"), std::string::npos) << cf.info.note;
}

// A broad hump (q 8) under a filter's roll-off: no bin of it stands out for the line search,
// but its band does, and it is the first of the periodogram's broad peaks.
TEST(DiagnoseSearch, BroadHumpIsTheFirstBroadPeak) {
  auto truth = white();
  truth.lowpass.taps = 1.15;
  truth.resonances.push_back({0.022, 12.0, 8.0});
  std::vector<double> y(static_cast<std::size_t>(kSamples));
  kernels::simulate_channel(truth, 5, 0, y, 1);
  const kernels::PsdResult psd = full_periodogram(y, kRate, 1);
  const auto peaks = broad_peaks(psd, 0.01, 3);
  ASSERT_FALSE(peaks.empty());
  // Within a band (1/16 octave) of f0, and well beyond the start threshold.
  EXPECT_LT(std::abs(std::log2(peaks.front().first / 12.0)), 1.0 / 16.0) << peaks.front().first;
  EXPECT_GT(peaks.front().second, 3.0 * kBroadPeakZ);
  for (const auto& [f, z] : peaks)
    EXPECT_GE(z, kBroadPeakZ);
}

// The curve holds a narrow resonance at 5 Hz that the record does not (its curve's best: q 380,
// inside its range, so the curve's own candidate stands without the periodogram) and the
// record's broad hump at 12 Hz. The hump, from the periodogram's broad peaks and confirmed
// there, fits the curve better, its fewer parameters charged, and is the candidate: before the
// other starts, the candidate was the 5 Hz resonance the record does not have.
TEST(DiagnoseSearch, ResonanceTheCurveMissesIsFoundFromTheBroadHump) {
  auto hump = white();
  hump.resonances.push_back({0.022, 12.0, 8.0});
  auto truth = hump;
  truth.resonances.push_back({0.05, 5.0, kernels::kResonanceMaxQ});
  Bases b;
  const Curve cv = exact_curve(truth, b);
  std::vector<double> y(static_cast<std::size_t>(kSamples));
  kernels::simulate_channel(hump, 5, 0, y, 1);
  const kernels::PsdResult psd = full_periodogram(y, kRate, 1);
  Witnesses seen;
  seen.periodogram = &psd;
  seen.record = y;
  const CandidateFit cf =
      resonance_candidate(components_of(white()), cv, b, seen, [](int k) { return 2.0 * k; });
  ASSERT_FALSE(cf.fit.comps.empty()) << cf.info.note;
  const auto& r = as<kernels::Resonance>(cf.fit.comps.back());
  EXPECT_NEAR(r.frequency_hz, 12.0, 0.5);
  EXPECT_TRUE(cf.fit.comps.back().psd_shape)
      << r.frequency_hz << " Hz, q " << r.q << ": " << cf.info.note;
  EXPECT_NE(cf.info.note.find("another start"), std::string::npos) << cf.info.note;
}

}  // namespace
}  // namespace allanlot
