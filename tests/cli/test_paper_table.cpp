// The paper's Table reproduced end to end: the embedded demo unit (Lestev et al. 2019, six
// channels at the Table's coefficients, 90 minutes at 1 kHz, accelerometer Z with 1 g) is
// simulated, analysed by the real binary, and the eq. (3) fit must recover the Table.
#include "io/results.hpp"
#include "kernels/model/units.hpp"
#include "src/lot/model.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace allanlot {
namespace {

using kernels::units::Term;

TEST(PaperTable, FitRecoversTheTableOnEveryChannel) {
  const auto dir = test::fresh_dir("paper_table");
  // A single unit from the demo model: its nominal coefficients, no lot spread drawn.
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " simulate --duration 5400 --seed 2019 -o " +
                                  (dir / "unit.h5").string(),
                              &out),
            0)
      << out;
  ASSERT_EQ(test::run_command(test::binary() + " analyze --stats oadev -o " +
                                  (dir / "out").string() + " " + (dir / "unit.h5").string(),
                              &out),
            0)
      << out;
  std::cout << out;
  const model::UnitModel truth = model::default_demo_model();
  const io::RecordingResult r = io::read_results(dir / "out" / "unit.allan.h5");
  ASSERT_EQ(r.channels.size(), 6u);
  int inside_3sigma = 0, checked = 0;
  for (const model::Channel& ch : truth.channels) {
    const io::ChannelResult* got = nullptr;
    for (const auto& c : r.channels)
      if (c.path == "/imu/" + ch.name) got = &c;
    ASSERT_NE(got, nullptr) << ch.name;
    ASSERT_TRUE(got->fit.has_value()) << ch.name;
    ASSERT_EQ(io::to_string(got->fit->status), "ok") << ch.name;
    const auto& terms = got->fit->terms;
    ASSERT_EQ(terms.size(), 5u);
    const auto& n = terms[static_cast<std::size_t>(Term::N)];
    const auto& b = terms[static_cast<std::size_t>(Term::B)];
    const auto& q = terms[static_cast<std::size_t>(Term::Q)];
    // The bounds: N within 5 %, B within 25 %, no quantization detected (the paper's
    // finding), both N and B detected.
    EXPECT_TRUE(n.detected) << ch.name;
    EXPECT_TRUE(b.detected) << ch.name;
    EXPECT_FALSE(q.detected) << ch.name;
    EXPECT_NEAR(n.value / ch.terms.N, 1.0, 0.05) << ch.name;
    EXPECT_NEAR(b.value / ch.terms.B, 1.0, 0.25) << ch.name;
    // Honest uncertainties: the truth within 3 sigma for nearly all detected terms.
    for (const auto& [t, value] :
         {std::pair{Term::N, ch.terms.N}, std::pair{Term::B, ch.terms.B}}) {
      const auto& tr = terms[static_cast<std::size_t>(t)];
      ++checked;
      if (std::abs(tr.value - value) <= 3 * tr.sigma) ++inside_3sigma;
    }
    // Equation (2) on the measured Welch PSD agrees with the time-domain overlapping Allan
    // variance within 12 % over the valid taus, which reach from 1 ms to at least 10 s.
    ASSERT_TRUE(got->psd.has_value()) << ch.name;
    EXPECT_EQ(got->psd->convention, "one-sided");
    EXPECT_GT(got->psd->f.size(), 20u);
    ASSERT_TRUE(got->crosscheck.has_value()) << ch.name;
    EXPECT_LT(got->crosscheck->max_abs_log10_ratio, std::log10(1.12)) << ch.name;
    std::size_t n_valid = 0;
    double tau_valid_max = 0;
    for (std::size_t i = 0; i < got->crosscheck->tau.size(); ++i)
      if (got->crosscheck->valid[i]) {
        ++n_valid;
        tau_valid_max = std::max(tau_valid_max, got->crosscheck->tau[i]);
      }
    EXPECT_GT(n_valid, 60u) << ch.name;
    EXPECT_GE(tau_valid_max, 10.0) << ch.name;
    // The PSD-domain fit (psd_fit/, the same datasets as fit/): N within 10 % (the issue's
    // bar; it is within a fraction of a percent), and the two fits agree term by term within
    // their uncertainties, which the lot summary reports as fits_agree.
    ASSERT_TRUE(got->psd_fit.has_value()) << ch.name;
    ASSERT_EQ(io::to_string(got->psd_fit->status), "ok") << ch.name;
    ASSERT_EQ(got->psd_fit->terms.size(), 5u);
    const auto& pn = got->psd_fit->terms[static_cast<std::size_t>(Term::N)];
    EXPECT_TRUE(pn.detected) << ch.name;
    EXPECT_NEAR(pn.value / ch.terms.N, 1.0, 0.10) << ch.name;
    EXPECT_EQ(pn.unit_datasheet, n.unit_datasheet);
    EXPECT_EQ(got->psd_fit->agree, 1)
        << ch.name << " max |z| " << got->psd_fit->max_abs_z << " on " << got->psd_fit->worst_term;
    EXPECT_EQ(got->psd_fit->f.size(), got->psd_fit->psd_model.size());
    // Not-detected terms: their 95 % upper bound is above the truth.
    for (const auto& tr : terms) {
      if (tr.detected) continue;
      const auto t = *kernels::units::parse_term(tr.term);
      const double true_value = t == Term::R   ? ch.terms.R
                                : t == Term::K ? ch.terms.K
                                : t == Term::Q ? ch.terms.Q
                                : t == Term::B ? ch.terms.B
                                               : ch.terms.N;
      EXPECT_GE(tr.upper, true_value) << ch.name << " " << tr.term;
    }
  }
  EXPECT_GE(inside_3sigma, checked - 1);  // "nearly all": at most one of twelve outside
  const auto summary = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(summary.size(), 6u);
  for (const auto& row : summary)
    EXPECT_EQ(row.fits_agree, 1) << row.channel;
  // The printed table is the paper's layout, in its units.
  EXPECT_NE(out.find("deg/h/sqrt(Hz)"), std::string::npos);
  EXPECT_NE(out.find("mg/sqrt(Hz)"), std::string::npos);
}

}  // namespace
}  // namespace allanlot
