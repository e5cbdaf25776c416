// The eq. (3) fit and the sensor's filter (docs/fit-and-psd.md "The sensor's filter"):
// a simulated filtered record (white + flicker + random walk through a first-order
// filter, kernels/simulate) fitted with the filter handled recovers N, B and K and fits within
// the chi-square its degrees of freedom allow; fitted over every tau it does not; an unfiltered
// record names no filter and its fit is bit for bit the fit over every tau.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

// Truth of the filtered unit: N, B, K in deg/s units (docs/formats.md "Units and conventions").
constexpr double kN = 0.005, kB = 0.002, kK = 1e-3;

void simulate(const fs::path& dir, const std::string& effects, int seed) {
  std::ofstream(dir / "model.json")
      << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": )" << kN << R"(, "B": )" << kB
      << R"(, "K": )" << kK << R"(}, "effects": [)" << effects << "]}";
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " simulate -q --model " +
                                  (dir / "model.json").string() + " --duration 3000 --seed " +
                                  std::to_string(seed) + " --channel gyro -o " +
                                  (dir / "u.h5").string(),
                              &out),
            0)
      << out;
}

io::FitRecord analyze(const fs::path& dir, const std::string& lowpass, std::string* out) {
  fs::remove_all(dir / "out");
  EXPECT_EQ(test::run_command(test::binary() + " analyze --no-progress --no-psd --lowpass " +
                                  lowpass + " -o " + (dir / "out").string() + " " +
                                  (dir / "u.h5").string(),
                              out),
            0)
      << *out;
  auto r = io::read_results(dir / "out" / "u.allan.h5");
  EXPECT_TRUE(r.channels.at(0).fit.has_value());
  return *r.channels.at(0).fit;
}

const io::TermRecord& term(const io::FitRecord& f, const std::string& name) {
  for (const auto& t : f.terms)
    if (t.term == name) return t;
  throw std::runtime_error("no term " + name);
}

TEST(FitLowpass, FilteredRecordFitsFromTheFirstUnbiasedTau) {
  const fs::path dir = test::fresh_dir("fit_lowpass_filtered");
  simulate(dir, R"({"type": "lowpass", "cutoff_hz": 15})", 23);
  std::string out;
  const io::FitRecord f = analyze(dir, "auto", &out);
  // Named from the curve: a first-order filter near 15 Hz (the candidate's grid steps 9 %),
  // the taus it biases left out, and the fit within what its degrees of freedom allow (status
  // ok: chi2 below the 99.9 % quantile of its expectation's chi-square).
  EXPECT_EQ(f.lowpass, "auto");
  ASSERT_TRUE(std::isfinite(f.lowpass_cutoff_hz)) << out;
  EXPECT_NEAR(f.lowpass_cutoff_hz, 15.0, 0.2 * 15.0);
  EXPECT_GT(f.lowpass_delta_ic, 0.0);
  EXPECT_GT(f.first_tau_fitted, 0.01);
  EXPECT_LT(f.taus_fitted, static_cast<std::int64_t>(f.tau.size()));
  EXPECT_EQ(f.status, kernels::FitStatus::Ok) << f.chi2_dof;
  // N, B and K within two of their own sigmas of the truth (value in channel units).
  for (const auto& [name, truth] : {std::pair{"N", kN}, {"B", kB}, {"K", kK}}) {
    const io::TermRecord& t = term(f, name);
    EXPECT_TRUE(t.detected) << name;
    EXPECT_NEAR(t.value, truth, 2.0 * t.sigma) << name;
  }
  EXPECT_NE(out.find("auto 1"), std::string::npos) << out;  // the table's lowpass row
  EXPECT_NE(out.find("fitted from"), std::string::npos) << out;

  // The same record fitted over every tau: the filter's deficit at the shortest taus, which
  // carry the most degrees of freedom, leaves the five terms far from the curve (this seed's
  // reweighting does not even settle), which is what leaving the taus out repairs.
  const io::FitRecord none = analyze(dir, "none", &out);
  EXPECT_EQ(none.lowpass, "none");
  EXPECT_NE(none.status, kernels::FitStatus::Ok);
  EXPECT_DOUBLE_EQ(none.chi2_dof, f.chi2_dof_all_taus);
  EXPECT_GT(none.chi2_dof, 10.0 * f.chi2_dof);

  // A filter given by the option is used as given and recorded as such.
  const io::FitRecord given = analyze(dir, "cutoff_hz=15", &out);
  EXPECT_EQ(given.lowpass, "option");
  EXPECT_DOUBLE_EQ(given.lowpass_cutoff_hz, 15.0);
  EXPECT_TRUE(std::isnan(given.lowpass_delta_ic));
  EXPECT_EQ(given.status, kernels::FitStatus::Ok) << given.chi2_dof;
}

TEST(FitLowpass, UnfilteredRecordIsFittedOverEveryTauAsBefore) {
  const fs::path dir = test::fresh_dir("fit_lowpass_plain");
  for (const int seed : {31, 32, 33}) {
    simulate(dir, "", seed);
    std::string out;
    const io::FitRecord f = analyze(dir, "auto", &out);
    // An ok fit over every tau is not tested (NaN); a poor one is, and names nothing.
    EXPECT_EQ(f.lowpass, "none") << "seed " << seed << " criterion " << f.lowpass_delta_ic;
    EXPECT_EQ(std::isnan(f.lowpass_delta_ic), f.status == kernels::FitStatus::Ok);
    EXPECT_FALSE(f.lowpass_delta_ic > 0.0);
    EXPECT_EQ(f.first_tau_fitted, f.tau.front());
    EXPECT_EQ(f.taus_fitted, static_cast<std::int64_t>(f.tau.size()));
    EXPECT_EQ(f.chi2_dof, f.chi2_dof_all_taus);
    const io::FitRecord none = analyze(dir, "none", &out);
    EXPECT_TRUE(std::isnan(none.lowpass_delta_ic));
    ASSERT_EQ(f.terms.size(), none.terms.size());
    for (std::size_t i = 0; i < f.terms.size(); ++i) {
      EXPECT_EQ(f.terms[i].value, none.terms[i].value) << f.terms[i].term;
      EXPECT_EQ(f.terms[i].sigma, none.terms[i].sigma) << f.terms[i].term;
    }
    EXPECT_EQ(f.adev_model, none.adev_model);
  }
}

// A filter found on the curve is applied only when it explains the misfit: here a small filter
// (a boxcar of 1.3 samples) beside a strong line (a sinusoid whose bump towers over the white
// noise at 1-5 s), as on the real accelerometers. The filter is found, but the fit from its
// first tau keeps the line's misfit on fewer taus, so it is recorded as auto-unused and every
// tau is fitted, bit for bit the fit of --lowpass none.
TEST(FitLowpass, AFilterThatDoesNotExplainTheMisfitIsNotApplied) {
  const fs::path dir = test::fresh_dir("fit_lowpass_line");
  simulate(dir,
           R"({"type": "lowpass", "taps": 1.3}, )"
           R"({"type": "sinusoid", "amplitude": 0.02, "frequency_hz": 0.15})",
           41);
  std::string out;
  const io::FitRecord f = analyze(dir, "auto", &out);
  EXPECT_NE(f.status, kernels::FitStatus::Ok) << f.chi2_dof;
  ASSERT_EQ(f.lowpass, "auto-unused") << "criterion " << f.lowpass_delta_ic << "\n" << out;
  EXPECT_GT(f.lowpass_delta_ic, 0.0);
  EXPECT_TRUE(std::isfinite(f.lowpass_taps) || std::isfinite(f.lowpass_cutoff_hz));
  EXPECT_EQ(f.first_tau_fitted, f.tau.front());
  EXPECT_EQ(f.taus_fitted, static_cast<std::int64_t>(f.tau.size()));
  EXPECT_EQ(f.chi2_dof, f.chi2_dof_all_taus);
  EXPECT_EQ(out.find("fitted from"), std::string::npos) << out;
  const io::FitRecord none = analyze(dir, "none", &out);
  ASSERT_EQ(f.terms.size(), none.terms.size());
  for (std::size_t i = 0; i < f.terms.size(); ++i)
    EXPECT_EQ(f.terms[i].value, none.terms[i].value) << f.terms[i].term;
  // Given by the option, the same filter is applied whatever the fit says.
  const io::FitRecord given = analyze(dir, "taps=1.3", &out);
  EXPECT_EQ(given.lowpass, "option");
  EXPECT_LT(given.taus_fitted, static_cast<std::int64_t>(given.tau.size()));
}

TEST(FitLowpass, BadOptionIsAUsageError) {
  const fs::path dir = test::fresh_dir("fit_lowpass_bad");
  simulate(dir, "", 5);
  for (const std::string bad : {"cutof_hz=3", "taps=0.5", "cutoff_hz=", "cutoff_hz=3x", "yes"}) {
    std::string out;
    EXPECT_EQ(test::run_command(test::binary() + " analyze --no-progress --lowpass " + bad +
                                    " -o " + (dir / "out").string() + " " + (dir / "u.h5").string(),
                                &out),
              2)
        << bad;
    EXPECT_NE(out.find("--lowpass"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace allanlot
