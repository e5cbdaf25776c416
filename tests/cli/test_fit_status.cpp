// The fit's status means something (docs/fit-and-psd.md "Fit status"): `ok` only when chi2 is
// within what the model's own noise allows, `poor fit (chi2/dof = X)` otherwise, in the results,
// the lot summary and the terminal, with a pointer to `diagnose`.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

std::string simulate_and_analyze(const fs::path& dir, const std::string& model, int* status,
                                 const std::string& options = "") {
  std::ofstream(dir / "model.json") << model;
  std::string out;
  EXPECT_EQ(test::run_command(
                test::binary() + " simulate -q --model " + (dir / "model.json").string() +
                    " --duration 2000 --seed 11 --channel gyro -o " + (dir / "u.h5").string(),
                &out),
            0)
      << out;
  *status = test::run_command(test::binary() + " analyze --no-progress " + options + " -o " +
                                  (dir / "out").string() + " " + (dir / "u.h5").string(),
                              &out);
  return out;
}

TEST(FitStatus, CleanNoiseIsOkAndASinusoidIsAPoorFit) {
  const fs::path dir = test::fresh_dir("fit_status");
  // White noise and bias instability only: the five terms describe it.
  int st = 0;
  std::string out = simulate_and_analyze(
      dir, R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.005, "B": 0.002}})", &st);
  ASSERT_EQ(st, 0) << out;
  auto r = io::read_results(dir / "out" / "u.allan.h5");
  ASSERT_TRUE(r.channels.at(0).fit.has_value());
  EXPECT_EQ(r.channels[0].fit->status, kernels::FitStatus::Ok) << r.channels[0].fit->chi2_dof;
  EXPECT_EQ(out.find("poor fit"), std::string::npos) << out;
  // The read-outs datasheets quote, beside the fit: N at 1 s as ARW (0.005 deg/sqrt(s) =
  // 0.3 deg/sqrt(h)), within a few of its uncertainties, in the terminal and the summary.
  const std::size_t arw = out.find("N at 1 s");
  ASSERT_NE(arw, std::string::npos) << out;
  EXPECT_EQ(out.substr(arw, out.find('\n', arw) - arw).find("deg/sqrt(h)"), 14u) << out;
  EXPECT_NE(out.find("B: min/0.664"), std::string::npos) << out;
  {
    const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].readout_n_alt_unit, "deg/sqrt(h)");
    EXPECT_NEAR(rows[0].readout_n_alt, 0.3, 5 * rows[0].readout_n_alt_sigma + 0.01);
    EXPECT_EQ(rows[0].readout_n_unit, "deg/h/sqrt(Hz)");
    EXPECT_EQ(rows[0].readout_b_unit, "deg/h");
    EXPECT_GT(rows[0].readout_b_tau, 0.0);
    EXPECT_NE(rows[0].readouts_valid.find('N'), std::string::npos);
  }
  // The same with a 0.05 Hz sinusoid far above the noise at its taus: the model misses it.
  // Eq. (3) alone (--model-poor-fits off): the model of a poor fit that analyze makes by default
  // is test_channel_model's.
  fs::remove_all(dir / "out");
  out = simulate_and_analyze(
      dir,
      R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.005, "B": 0.002},
          "effects": [{"type": "sinusoid", "amplitude": 0.05, "frequency_hz": 0.05}]})",
      &st, "--model-poor-fits off");
  ASSERT_EQ(st, 0) << out;
  r = io::read_results(dir / "out" / "u.allan.h5");
  ASSERT_TRUE(r.channels.at(0).fit.has_value());
  const io::FitRecord& fit = *r.channels[0].fit;
  EXPECT_EQ(fit.status, kernels::FitStatus::PoorFit);
  EXPECT_GT(fit.chi2_dof, 3.0);
  const std::string text = io::fit_status_text(fit);
  EXPECT_TRUE(text.starts_with("poor fit (chi2/dof = ")) << text;
  // Terminal: the status under the coefficients, and what to do about it.
  EXPECT_NE(out.find(text), std::string::npos) << out;
  EXPECT_NE(out.find("allanlot diagnose"), std::string::npos) << out;
  // Lot summary: its own column.
  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].fit_status, text);
  // The report says it beside the channel, with the read-outs under the coefficients.
  ASSERT_EQ(test::run_command(test::binary() + " report " + (dir / "out").string(), &out), 0)
      << out;
  const std::string html = test::file_bytes(dir / "out" / "report.html");
  EXPECT_NE(html.find("fit " + text), std::string::npos);
  EXPECT_NE(html.find("<code>allanlot diagnose</code> names what"), std::string::npos);
  EXPECT_NE(html.find("N at 1 s</td>"), std::string::npos);
  EXPECT_NE(html.find("B: min / 0.664</td>"), std::string::npos);
  // The coefficients are still given: they are what the data gave.
  EXPECT_TRUE(kernels::has_terms(fit.status));
  EXPECT_FALSE(fit.terms.empty());
}

}  // namespace
}  // namespace allanlot
