// ITU-T masks (src/lot/masks.hpp): their values at the tables' corners, the per-tau judgement
// of a curve, the spec rule "mtie"/"tdev": {"mask": ...} through analyze's lot summary, and the
// masks on the report's time-error plot; and a hat's results as a report section.
#include "io/results.hpp"
#include "src/lot/masks.hpp"
#include "src/lot/spec.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

double ns(const char* name, const char* stat, double tau) {
  const masks::Mask* m = masks::find_mask(name, stat);
  EXPECT_NE(m, nullptr) << name << " " << stat;
  return m ? 1e9 * masks::limit_s(*m, tau) : std::nan("");
}

TEST(Masks, ValuesOfTheTables) {
  // G.811 Table 1 and 2.
  EXPECT_NEAR(ns("G.811", "mtie", 1.0), 25.275, 1e-9);
  EXPECT_NEAR(ns("G.811", "mtie", 1000.0), 300.0, 1e-9);
  EXPECT_NEAR(ns("G.811", "mtie", 10000.0), 390.0, 1e-9);
  EXPECT_NEAR(ns("G.811", "tdev", 50.0), 3.0, 1e-12);
  EXPECT_NEAR(ns("G.811", "tdev", 500.0), 15.0, 1e-9);
  EXPECT_NEAR(ns("G.811", "tdev", 5000.0), 30.0, 1e-12);
  // G.813 option 1 = G.8262 option 1: Tables 1 and 3.
  for (const char* name : {"G.813", "G.8262"}) {
    EXPECT_NEAR(ns(name, "mtie", 0.5), 40.0, 1e-12) << name;
    EXPECT_NEAR(ns(name, "mtie", 10.0), 40.0 * std::pow(10.0, 0.1), 1e-9) << name;
    EXPECT_NEAR(ns(name, "mtie", 1000.0), 25.25 * std::pow(1000.0, 0.2), 1e-9) << name;
    EXPECT_NEAR(ns(name, "tdev", 10.0), 3.2, 1e-12) << name;
    EXPECT_NEAR(ns(name, "tdev", 64.0), 0.64 * 8.0, 1e-9) << name;
    EXPECT_NEAR(ns(name, "tdev", 1000.0), 6.4, 1e-12) << name;
  }
  // G.8262 option 2: Tables 4 and 5.
  EXPECT_NEAR(ns("G.8262-option2", "mtie", 5.0), 20.0 * std::pow(5.0, 0.48), 1e-9);
  EXPECT_NEAR(ns("G.8262-option2", "tdev", 1.0), 3.2, 1e-9);
  EXPECT_NEAR(ns("G.8262-option2", "tdev", 20.0), 2.0, 1e-12);
  EXPECT_NEAR(ns("G.8262-option2", "tdev", 5000.0), 10.0, 1e-12);
  // Outside the taus: no limit.
  EXPECT_TRUE(std::isnan(ns("G.813", "tdev", 0.05)));
  EXPECT_TRUE(std::isnan(ns("G.813", "tdev", 2000.0)));
  EXPECT_EQ(masks::find_mask("G.999", "mtie"), nullptr);
  EXPECT_EQ(masks::find_mask("G.811", "adev"), nullptr);
}

// Each mask is continuous to the tables' rounding where its pieces meet: under 1.5 % (G.8262
// option 2's TDEV, 3.2 tau^-0.5 ns = 2.02 ns at 2.5 s against the 2 ns that follow, is the
// widest); a mistyped coefficient or exponent moves a join by far more.
TEST(Masks, PiecesMeet) {
  for (const masks::Mask& m : masks::all_masks())
    for (std::size_t k = 1; k < m.segments.size(); ++k) {
      const masks::Segment &a = m.segments[k - 1], &b = m.segments[k];
      ASSERT_EQ(a.hi_s, b.lo_s) << m.name << " " << m.stat;
      const double t = a.hi_s;
      const double left = a.a_ns + a.b_ns * std::pow(t, a.p);
      const double right = b.a_ns + b.b_ns * std::pow(t, b.p);
      EXPECT_NEAR(left / right, 1.0, 0.015) << m.name << " " << m.stat << " at " << t << " s";
    }
}

kernels::StatResult curve(std::vector<double> tau, std::vector<double> dev,
                          std::vector<double> lo = {}, std::vector<double> hi = {}) {
  kernels::StatResult r;
  r.tau_s = tau;
  r.dev = dev;
  r.m.assign(tau.size(), 1);
  r.dev_lo = lo.empty() ? std::vector<double>(tau.size(), std::nan("")) : lo;
  r.dev_hi = hi.empty() ? std::vector<double>(tau.size(), std::nan("")) : hi;
  return r;
}

TEST(Masks, JudgedPerTau) {
  using O = masks::CurveVerdict::Outcome;
  const masks::Mask& tdev = *masks::find_mask("G.811", "tdev");
  // 3 ns up to 100 s: 2 ns passes, 4 ns at one tau fails, a straddling interval is undecided.
  EXPECT_EQ(masks::judge_curve(tdev, curve({1, 10, 100}, {2e-9, 2e-9, 2e-9},
                                           {1.5e-9, 1.5e-9, 1.5e-9}, {2.5e-9, 2.5e-9, 2.5e-9}))
                .outcome,
            O::Pass);
  const auto f = masks::judge_curve(tdev, curve({1, 10, 100}, {2e-9, 4e-9, 2e-9},
                                                {1.5e-9, 3.5e-9, 1.5e-9}, {2.5e-9, 5e-9, 2.5e-9}));
  EXPECT_EQ(f.outcome, O::Fail);
  EXPECT_EQ(f.worst_tau_s, 10.0);
  EXPECT_EQ(f.detail, "tdev 4e-09 s > G.811 3e-09 s at tau 10 s");
  EXPECT_EQ(masks::judge_curve(tdev, curve({10}, {2.9e-9}, {2.5e-9}, {3.2e-9})).outcome,
            O::Undecided);
  // Taus outside the mask are not judged; none inside: undecided.
  EXPECT_EQ(masks::judge_curve(tdev, curve({0.01, 1e5}, {1.0, 1.0})).outcome, O::Undecided);
  // MTIE has no interval: its value decides.
  const masks::Mask& mtie = *masks::find_mask("G.811", "mtie");
  EXPECT_EQ(masks::judge_curve(mtie, curve({1000}, {2.99e-7})).outcome, O::Pass);
  EXPECT_EQ(masks::judge_curve(mtie, curve({1000}, {3.01e-7})).outcome, O::Fail);
}

TEST(Masks, SpecRules) {
  const auto s = spec::parse_spec(
      R"({"channels": {"phase": {"mtie": {"mask": "G.811"}, "tdev": {"mask": "G.8262"}}}})",
      "s.json");
  ASSERT_EQ(s.rules.size(), 1u);
  ASSERT_EQ(s.rules[0].masks.size(), 2u);
  EXPECT_EQ(s.rules[0].masks[1].stat, "tdev");
  EXPECT_EQ(s.rules[0].masks[1].mask, "G.8262");
  try {
    spec::parse_spec(R"({"channels": {"x": {"mtie": {"mask": "G.999"}, "tdev": {"max": 1}}}})",
                     "s.json");
    FAIL() << "a bad mask was taken";
  } catch (const spec::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("s.json: channels.x.mtie.mask: no mtie mask 'G.999' (masks: G.811, "),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("channels.x.tdev.max: unknown key"), std::string::npos) << what;
    EXPECT_NE(what.find("channels.x.tdev.mask: missing"), std::string::npos) << what;
  }
}

// A phase recording in s of white PM of `sigma` s: its TDEV at tau = m is sigma / sqrt(m)
// (so 1 ns passes G.811's 3 ns from 0.1 s on, 100 ns fails it).
void write_clock(const fs::path& file, double sigma, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> d(0.0, sigma);
  std::vector<double> x(2000);
  for (double& v : x)
    v = d(gen);
  test::H5Fixture f(file);
  f.group("/clock");
  f.attr("/clock", "sample_rate_hz", 1.0);
  f.dataset("/clock/phase", x, H5T_IEEE_F64LE);
  f.attr("/clock/phase", "units", std::string("s"));
  f.attr("/clock/phase", "data_type", std::string("phase"));
}

TEST(Masks, AnalyzeJudgesAndReportDraws) {
  const fs::path d = test::fresh_dir("masks_e2e");
  fs::create_directories(d / "in");
  write_clock(d / "in" / "good.h5", 1e-9, 1);
  write_clock(d / "in" / "bad.h5", 1e-7, 2);
  const fs::path sp = d / "spec.json";
  std::ofstream(sp) << R"({"channels": {"phase": {"tdev": {"mask": "G.811"},
                                                   "mtie": {"mask": "G.811"}}}})";
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-fit --no-psd --stats tdev,mtie --spec " +
                            sp.string() + " -o " + (d / "res").string() + " " + (d / "in").string(),
                        &out),
            0)
      << out;
  const auto rows = io::read_lot_summary(d / "res" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) {
    if (r.device_id == "good") {
      EXPECT_EQ(r.spec_status, "pass") << r.spec_detail;
      EXPECT_NE(r.spec_detail.find("<= G.811"), std::string::npos) << r.spec_detail;
    } else {
      EXPECT_EQ(r.spec_status, "fail") << r.spec_detail;
      EXPECT_NE(r.spec_detail.find("tdev "), std::string::npos) << r.spec_detail;
    }
  }
  ASSERT_EQ(
      run_command(binary() + " report -q --spec " + sp.string() + " " + (d / "res").string(), &out),
      0)
      << out;
  std::ifstream in(d / "res" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("G.811 TDEV mask"), std::string::npos);
  EXPECT_NE(html.find("G.811 MTIE mask"), std::string::npos);
  EXPECT_EQ(run_command(binary() + " report -q --spec " + (d / "none.json").string() + " " +
                            (d / "res").string(),
                        &out),
            2)
      << out;
}

// A hat's results file in a folder of results: the report gives its clocks a section with each
// clock's deviation and interval.
TEST(Masks, ReportShowsAHat) {
  const fs::path d = test::fresh_dir("masks_hat_report");
  fs::create_directories(d / "res");
  std::string inputs;
  for (const char* p : {"AB", "AC", "BC"}) {
    write_clock(d / (std::string(p) + ".h5"), 1e-9, static_cast<std::uint64_t>(p[1]));
    inputs += " " + (d / (std::string(p) + ".h5")).string();
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " hat --clocks A,B,C --taus octave" + inputs + " -o " +
                            (d / "res" / "clocks.allan.h5").string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(binary() + " report -q " + (d / "res").string(), &out), 0) << out;
  std::ifstream in(d / "res" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("Clocks by the 3-cornered hat"), std::string::npos);
  EXPECT_NE(html.find("<th>A lower</th><th>A</th><th>A upper</th>"), std::string::npos);
  EXPECT_NE(html.find("clock C (bars: 68.3 % CI)"), std::string::npos);
}

}  // namespace
}  // namespace allanlot
