// `allanlot report` end to end through the binary, on a small simulated lot (five units of two
// channels and one unit with five times the white noise): the page is self-contained and
// deterministic, has the expected plots, finds the odd unit as an outlier (exactly the lot
// summary's outliers), splits into linked unit pages, shows a diagnosis group and the lot
// summary's spec colouring when present, and fails with clear messages.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <fstream>
#include <map>
#include <regex>
#include <set>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

std::string read_file(const fs::path& p) {
  return test::file_bytes(p);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1))
    ++n;
  return n;
}

class Report : public ::testing::Test {
protected:
  static fs::path dir() { return fs::path(ALLANLOT_TEST_TMP) / "report"; }
  static fs::path results() { return dir() / "results"; }

  // One lot for every test of this file: simulated and analysed once (a few seconds).
  static void SetUpTestSuite() {
    const fs::path d = test::fresh_dir("report");
    {
      std::ofstream m(d / "lot.json");
      m << R"({"sample_rate_hz": 100, "lot_spread": {"N": 0.05, "B": 0.1},
               "channels": {
                 "gyro_x": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.001}},
                 "accel_x": {"units": "m/s^2", "terms": {"N": 0.002, "B": 0.0005}}}})";
      std::ofstream o(d / "odd.json");
      o << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.03, "B": 0.001}})";
    }
    std::string out;
    ASSERT_EQ(run_command(binary() + " simulate -q --model " + (d / "lot.json").string() +
                              " --lot 5 --duration 300 --seed 7 -o " + (d / "lot").string(),
                          &out),
              0)
        << out;
    ASSERT_EQ(run_command(binary() + " simulate -q --model " + (d / "odd.json").string() +
                              " --duration 300 --seed 8 -o " + (d / "lot" / "odd_unit.h5").string(),
                          &out),
              0)
        << out;
    ASSERT_EQ(
        run_command(binary() + " analyze -q -o " + results().string() + " " + (d / "lot").string(),
                    &out),
        0)
        << out;
  }

  static std::string report(const std::string& args, int expect = 0) {
    std::string out;
    EXPECT_EQ(run_command(binary() + " report " + args, &out), expect) << args << "\n" << out;
    return out;
  }
};

TEST_F(Report, WritesASelfContainedPageWithThePlots) {
  const fs::path html = dir() / "r1.html";
  report(results().string() + " -o " + html.string());
  const std::string s = read_file(html);
  ASSERT_FALSE(s.empty());
  EXPECT_EQ(s.rfind("<!DOCTYPE html>", 0), 0u);
  // Nothing fetched, nothing run: no scripts, no external resources (the SVG namespace URI is
  // an identifier, never fetched).
  EXPECT_EQ(s.find("<script"), std::string::npos);
  EXPECT_EQ(s.find(" src="), std::string::npos);
  EXPECT_EQ(s.find("@import"), std::string::npos);
  EXPECT_EQ(count(s, "http"), count(s, "http://www.w3.org/2000/svg"));
  // Per unit and channel: the Allan plot, the PSD and the cross-check; per channel of the lot:
  // a distribution plot.
  for (int u = 1; u <= 5; ++u)
    for (const char* c : {"accel_x", "gyro_x"})
      for (const char* kind : {"adev", "tdev", "psd", "xc"}) {
        const std::string id = "id=\"u-unit_000" + std::to_string(u) + "-_imu_" + c + "-" + kind;
        EXPECT_NE(s.find(id + "\""), std::string::npos) << id;
      }
  EXPECT_NE(s.find("id=\"u-odd_unit-_imu_gyro_x-adev\""), std::string::npos);
  EXPECT_EQ(count(s, "<svg "), 11u * 4u + 2u);
  EXPECT_NE(s.find("id=\"dist-_imu_gyro_x\""), std::string::npos);
  EXPECT_NE(s.find("id=\"dist-_imu_accel_x\""), std::string::npos);
  // The fit's asymptotes, labelled with their slopes, and the coefficient table.
  EXPECT_NE(s.find("N: slope \xE2\x88\x92"
                   "1/2"),
            std::string::npos);
  EXPECT_NE(s.find("deg/h/sqrt(Hz)"), std::string::npos);
  EXPECT_NE(s.find("Equation (3) coefficients"), std::string::npos);
  // The plots in the table's units (a gyro's deviations in deg/h, its TDEV in urad), the other
  // statistics behind tick boxes, the deviation tables folded away.
  EXPECT_NE(s.find("\xCF\x83(\xCF\x84) (deg/h)</text>"), std::string::npos);
  EXPECT_NE(s.find("\xCF\x83(\xCF\x84) (mg)</text>"), std::string::npos);
  EXPECT_NE(s.find("time error (urad)</text>"), std::string::npos);
  EXPECT_EQ(s.find("(deg/s)</text>"), std::string::npos);
  EXPECT_NE(s.find("<input type=\"checkbox\" id=\"u-unit_0001-_imu_gyro_x-adev-t-mdev\""),
            std::string::npos);
  EXPECT_NE(s.find(".t-mdev:checked~svg .s-mdev{display:inline}"), std::string::npos);
  EXPECT_NE(s.find("<details class=\"devtables\" id=\"u-unit_0001-_imu_gyro_x-devtables\">"),
            std::string::npos);
  EXPECT_NE(s.find("id=\"u-unit_0001-_imu_gyro_x-dev-oadev\""), std::string::npos);
}

// Without the fit and the PSD, only what was computed: no fit wording, no PSD or cross-check
// panel, no empty distribution frame; the deviations and TDEV are still there.
TEST_F(Report, ShowsOnlyWhatWasComputed) {
  const fs::path nofit = dir() / "nofit";
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-fit --no-psd -o " + nofit.string() + " " +
                            (dir() / "lot").string(),
                        &out),
            0)
      << out;
  report(nofit.string() + " -q");
  const std::string s = read_file(nofit / "report.html");
  EXPECT_EQ(s.find("eq. (3) fit"), std::string::npos);
  EXPECT_EQ(s.find("id=\"dist-"), std::string::npos);
  EXPECT_EQ(s.find("-psd\""), std::string::npos);
  EXPECT_EQ(s.find("-xc\""), std::string::npos);
  EXPECT_EQ(count(s, "<svg "), 11u * 2u);
  EXPECT_NE(s.find("no unit has a fitted noise term"), std::string::npos);
}

TEST_F(Report, IsDeterministic) {
  report(results().string() + " -q -o " + (dir() / "d1.html").string());
  report(results().string() + " -q -o " + (dir() / "d2.html").string());
  const std::string a = read_file(dir() / "d1.html"), b = read_file(dir() / "d2.html");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == b);
}

TEST_F(Report, NamesTheOddUnitAsAnOutlier) {
  report(results().string() + " -q -o " + (dir() / "o.html").string());
  const std::string s = read_file(dir() / "o.html");
  const auto at = s.find("<h2>Outlier units</h2>");
  ASSERT_NE(at, std::string::npos);
  const std::string section = s.substr(at, s.find("<h2>", at + 5) - at);
  EXPECT_NE(section.find("href=\"#u-odd_unit-_imu_gyro_x\">odd_unit</a>"), std::string::npos)
      << section;
  EXPECT_EQ(section.find("unit_000"), std::string::npos) << section;
}

// The report judges outliers with the lot summary's rule (src/lot/statistics.hpp), so on the
// lot with a planted outlier (odd_unit, with six times the others' white noise) its outlier table
// lists exactly the (unit, channel, term) of lot_summary.h5's outlier_terms, with the same z
// (the report prints 3 significant digits, the summary 2).
TEST_F(Report, OutlierListEqualsTheLotSummarys) {
  report(results().string() + " -q -o " + (dir() / "same.html").string());
  const std::string s = read_file(dir() / "same.html");
  const auto at = s.find("<h2>Outlier units</h2>");
  ASSERT_NE(at, std::string::npos);
  const std::string section = s.substr(at, s.find("<h2>", at + 5) - at);
  std::map<std::string, double> in_report;
  const std::regex row("<tr><td class=\"l\"><a href=\"[^\"]*\">([^<]*)</a></td>"
                       "<td class=\"l\">([^<]*)</td><td>([RKBNQ])</td>(?:<td[^>]*>[^<]*</td>){3}"
                       "<td>([^<]*)</td></tr>");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), row);
       it != std::sregex_iterator(); ++it)
    in_report[(*it)[1].str() + " " + (*it)[2].str() + " " + (*it)[3].str()] =
        std::stod((*it)[4].str());
  std::map<std::string, double> in_summary;
  const std::regex term("([RKBNQ]) z=([-+0-9.e]+)");
  for (const io::SummaryRow& r : io::read_lot_summary(results() / "lot_summary.h5"))
    for (auto it = std::sregex_iterator(r.outlier_terms.begin(), r.outlier_terms.end(), term);
         it != std::sregex_iterator(); ++it)
      in_summary[r.device_id + " " + r.channel + " " + (*it)[1].str()] = std::stod((*it)[2].str());
  ASSERT_EQ(in_summary.count("odd_unit /imu/gyro_x N"), 1u);  // the planted outlier
  ASSERT_EQ(in_report.size(), in_summary.size()) << section;
  for (const auto& [key, z] : in_summary) {
    ASSERT_EQ(in_report.count(key), 1u) << key << "\n" << section;
    EXPECT_NEAR(in_report[key], z, 0.055 * std::abs(z)) << key;
  }
}

TEST_F(Report, SplitsIntoLinkedUnitPages) {
  const fs::path out = dir() / "split";
  fs::remove_all(out);
  fs::create_directories(out);
  report(results().string() + " -q --unit-pages always -o " + (out / "lot.html").string());
  const std::string lot = read_file(out / "lot.html");
  EXPECT_EQ(count(lot, "<svg "), 2u);  // only the distributions
  for (const char* u : {"unit_0001", "unit_0005", "odd_unit"})
    EXPECT_TRUE(fs::exists(out / "lot_units" / (std::string(u) + ".html"))) << u;
  // Every link of the lot page resolves: the file exists and holds the anchor.
  const std::regex href("href=\"([^\"#]*)#([^\"]*)\"");
  std::size_t checked = 0;
  for (auto it = std::sregex_iterator(lot.begin(), lot.end(), href); it != std::sregex_iterator();
       ++it) {
    const std::string file = (*it)[1], anchor = (*it)[2];
    const std::string target = file.empty() ? lot : read_file(out / file);
    EXPECT_NE(target.find("id=\"" + anchor + "\""), std::string::npos) << file << "#" << anchor;
    ++checked;
  }
  EXPECT_GT(checked, 10u);
  const std::string page = read_file(out / "lot_units" / "unit_0002.html");
  EXPECT_NE(page.find("href=\"../lot.html#lot\""), std::string::npos);
  EXPECT_EQ(count(page, "<svg "), 8u);  // per channel: Allan, TDEV, PSD, cross-check
}

// A diagnose output as io/diagnosis.hpp writes it: /<channel>/diagnosis with the curves as
// variances, the Monte Carlo bands, per-iteration effects, gaps and parameters, and the gaps as
// attributes. The `malformed` variant has datasets the schema does not know (alternative names
// such as avar_mc_lo, which are not read: no alias guessing), an effects attribute instead of a
// dataset, only the per-iteration gaps after, and a curve of the wrong length.
// diagnose's verdict on a channel: its gap after, its replicas' p95 and their number.
struct Verdict {
  double gap_after = 1.05, p95 = 1.2;
  int replicas = 30;
};

void write_diagnosis(const fs::path& path, const std::string& device, bool malformed,
                     const Verdict& v = {}) {
  test::H5Fixture f(path);
  f.group("/imu/gyro_x/diagnosis");
  f.attr("/", "device_id", device);
  const std::string g = "/imu/gyro_x/diagnosis/";
  std::vector<double> tau, meas, before, after, lo, hi, edf;
  for (int k = 0; k < 20; ++k) {
    const double t = 0.01 * std::pow(10.0, k * 0.2);
    tau.push_back(t);
    after.push_back(2.5e-5 / t + 1e-6);
    before.push_back(2.5e-5 / t);
    meas.push_back(after.back() * (1 + 0.05 * std::sin(k)));
    lo.push_back(after.back() * 0.8);
    hi.push_back(after.back() * 1.25);
    edf.push_back(100.0 / (1 + k));
  }
  f.dataset(g + "tau", tau, H5T_IEEE_F64LE);
  f.dataset(g + "avar_measured", meas, H5T_IEEE_F64LE);
  f.dataset(g + "avar_model_before", malformed ? std::vector<double>{1, 2, 3} : before,
            H5T_IEEE_F64LE);
  f.dataset(g + "avar_model_after", after, H5T_IEEE_F64LE);
  f.dataset(g + (malformed ? "avar_mc_lo" : "mc_after_lo"), lo, H5T_IEEE_F64LE);
  f.dataset(g + (malformed ? "avar_mc_hi" : "mc_after_hi"), hi, H5T_IEEE_F64LE);
  f.dataset(g + "edf", edf, H5T_IEEE_F64LE);
  if (malformed) {
    f.dataset(g + "gap_iteration_after", {4.2, 1.9, 1.05}, H5T_IEEE_F64LE);
    f.attr(g, "effects_named", std::string("[\"sinusoid\", \"markov\"]"));
    f.string_dataset(g + "edf_text", {"not", "numbers"});
  } else {
    f.string_dataset(g + "effect", {"sinusoid", "markov"});
    f.string_dataset(g + "parameters", {R"({"parameters": {"amplitude": 0.006}})", "{}"});
    f.dataset(g + "gap_iteration_before", {4.2, 1.9}, H5T_IEEE_F64LE);
    f.dataset(g + "gap_iteration_after", {1.9, 1.05}, H5T_IEEE_F64LE);
    f.dataset(g + "delta_ic", {-120, -14}, H5T_IEEE_F64LE);
    f.attr(g, "gap_before", 4.2);
    f.attr(g, "gap_after", v.gap_after);
    f.attr(g, "gap_noise_p95", v.p95);
    f.attr(g, "mc_replicas", static_cast<double>(v.replicas));
    f.attr(g, "gap_within_noise", v.gap_after <= v.p95 ? 1.0 : 0.0);
    f.attr(g, "model_after", std::string(R"({"units": "deg/s"})"));
    f.attr(g, "report",
           std::string(R"({"notes": ["round 2: the record without its least-squares line )"
                       R"(still shows the random walk"]})"));
  }
}

TEST_F(Report, ShowsADiagnosisWhenThereIsOne) {
  const fs::path d = test::fresh_dir("report_diag");
  write_diagnosis(d / "diag.h5", "unit_0002", false);
  write_diagnosis(d / "bad.h5", "unit_0003", true);
  report(results().string() + " -q --diagnosis " + (d / "diag.h5").string() + " --diagnosis " +
         (d / "bad.h5").string() + " -o " + (d / "r.html").string());
  const std::string s = read_file(d / "r.html");
  EXPECT_NE(s.find("id=\"u-unit_0002-_imu_gyro_x-diag\""), std::string::npos);
  EXPECT_NE(s.find("<b>sinusoid</b> &rarr; <b>markov</b>"), std::string::npos);
  EXPECT_NE(s.find("Gap before: 4.2, after: 1.05"), std::string::npos);
  EXPECT_NE(s.find("Monte Carlo band"), std::string::npos);
  EXPECT_NE(s.find("<td class=\"l wrap\">amplitude = 0.006</td>"), std::string::npos);
  EXPECT_NE(s.find("<td>-120</td>"), std::string::npos);  // delta IC
  // diagnose's notes, from its JSON report: why each round chose what it did.
  EXPECT_NE(s.find("<p class=\"small\">round 2: the record without its least-squares line "
                   "still shows the random walk</p>"),
            std::string::npos);
  // The malformed one: the short curve left out with a note, the gap after from the last
  // iteration.
  EXPECT_NE(s.find("id=\"u-unit_0003-_imu_gyro_x-diag\""), std::string::npos);
  EXPECT_NE(s.find("a curve has 3 values for 20 taus; not drawn"), std::string::npos);
  EXPECT_NE(s.find("Gap before: -, after: 1.05"), std::string::npos);  // last iteration's
  // A diagnosis file dropped into OUTDIR is found without --diagnosis.
  const fs::path out = test::fresh_dir("report_diag_auto");
  for (const char* u : {"unit_0001.allan.h5", "unit_0002.allan.h5"})
    fs::copy_file(results() / u, out / u);
  write_diagnosis(out / "unit_0002.diagnosis.h5", "unit_0002", false);
  report(out.string() + " -q");
  EXPECT_NE(read_file(out / "report.html").find("id=\"u-unit_0002-_imu_gyro_x-diag\""),
            std::string::npos);
}

TEST_F(Report, CountsTheLotsDiagnosesBeyondNoiseAgainstChance) {
  // Two channels judged against the p95 of 30 replicas, one beyond it, and one malformed
  // diagnosis without a verdict. A complete model is beyond that p95 with probability
  // 1.55 / 31 = 0.05 (kernels/diagnose/lot_noise.hpp), so one or more of two with probability
  // 1 - (1 - 0.05)^2 = 0.0975: no more than chance.
  const fs::path d = test::fresh_dir("report_diag_lot");
  write_diagnosis(d / "a.h5", "unit_0001", false, {1.5, 1.3, 30});
  write_diagnosis(d / "b.h5", "unit_0002", false, {0.9, 1.3, 30});
  write_diagnosis(d / "c.h5", "unit_0003", true);
  report(results().string() + " -q --diagnosis " + (d / "a.h5").string() + " --diagnosis " +
         (d / "b.h5").string() + " --diagnosis " + (d / "c.h5").string() + " -o " +
         (d / "r.html").string());
  const std::string s = read_file(d / "r.html");
  EXPECT_NE(s.find("<h2>Diagnoses</h2>\n<p>3 channels diagnosed: 1 within statistical noise"),
            std::string::npos);
  EXPECT_NE(s.find("1 beyond. Were every model complete, a channel would be beyond with "
                   "probability 0.05 (its quantile from 30 replicas): 0.1 expected, 1 or more "
                   "with probability 0.098. No more than chance"),
            std::string::npos);
  EXPECT_NE(s.find("1 diagnoses have no verdict to count"), std::string::npos);
  EXPECT_NE(s.find("unit_0001</a></td><td class=\"l\">/imu/gyro_x</td><td>1.5</td><td>1.3</td>"
                   "<td>30</td>"),
            std::string::npos);
  EXPECT_EQ(s.find("unit_0002</a></td><td class=\"l\">/imu/gyro_x</td><td>0.9</td>"),
            std::string::npos);
  // Both channels beyond is more than chance: 0.05^2 = 0.0025.
  const fs::path m = test::fresh_dir("report_diag_lot_both");
  write_diagnosis(m / "a.h5", "unit_0001", false, {1.5, 1.3, 30});
  write_diagnosis(m / "b.h5", "unit_0002", false, {1.4, 1.3, 30});
  report(results().string() + " -q --diagnosis " + (m / "a.h5").string() + " --diagnosis " +
         (m / "b.h5").string() + " -o " + (m / "r.html").string());
  EXPECT_NE(read_file(m / "r.html")
                .find("2 or more with probability 0.0025. <span "
                      "class=\"bad\">More than chance gives a lot of complete "
                      "models"),
            std::string::npos);
}

// A lot summary with the spec columns the lead is adding (whole-row and per-term status,
// fits_agree), written beside copies of the results files.
void write_summary_with_spec(const fs::path& path) {
  struct Rec {
    const char* device_id;
    const char* channel;
    const char* status;
    const char* spec_status;
    const char* n_spec;
    double fits_agree;
  };
  const Rec recs[] = {{"unit_0001", "/imu/gyro_x", "ok", "pass", "pass", 1.0},
                      {"unit_0002", "/imu/gyro_x", "ok", "fail", "fail", 0.0},
                      {"unit_0003", "/imu/gyro_x", "ok", "undecided", "undecided", 1.0},
                      {"lost_unit", "", "failed: cannot open", "", "", NAN}};
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t str = H5Tcopy(H5T_C_S1);
  H5Tset_size(str, H5T_VARIABLE);
  const hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(Rec));
  H5Tinsert(t, "device_id", offsetof(Rec, device_id), str);
  H5Tinsert(t, "channel", offsetof(Rec, channel), str);
  H5Tinsert(t, "status", offsetof(Rec, status), str);
  H5Tinsert(t, "spec_status", offsetof(Rec, spec_status), str);
  H5Tinsert(t, "N_spec_status", offsetof(Rec, n_spec), str);
  H5Tinsert(t, "fits_agree", offsetof(Rec, fits_agree), H5T_NATIVE_DOUBLE);
  const hsize_t n = 4;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t ds = H5Dcreate2(f, "summary", t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, recs);
  H5Dclose(ds);
  H5Sclose(space);
  H5Tclose(t);
  H5Tclose(str);
  H5Fclose(f);
}

TEST_F(Report, ColoursSpecStatusFromTheLotSummary) {
  const fs::path d = test::fresh_dir("report_spec");
  for (const auto& e : fs::directory_iterator(results()))
    if (e.path().extension() == ".h5" && e.path().filename() != "lot_summary.h5")
      fs::copy_file(e.path(), d / e.path().filename());
  write_summary_with_spec(d / "lot_summary.h5");
  report(d.string() + " -q");
  const std::string s = read_file(d / "report.html");
  EXPECT_NE(s.find("<td class=\"verdict pass\"><b>pass</b></td>"), std::string::npos);
  EXPECT_NE(s.find("<td class=\"verdict fail\"><b>fail</b></td>"), std::string::npos);
  EXPECT_NE(s.find("<td class=\"verdict undecided\"><b>undecided</b></td>"), std::string::npos);
  EXPECT_NE(s.find("<td class=\"bad\">no</td>"), std::string::npos);  // fits disagree
  // A summary without the unit columns: the units' verdicts judged from the channels' by the one
  // rule (one channel each here), the failed input without a verdict.
  EXPECT_NE(s.find("<b>Units against the spec:</b> <span class=\"pass\">1 pass</span> <span "
                   "class=\"fail\">1 fail</span> <span class=\"undecided\">1 undecided</span> "
                   "<span>1 no spec or no data</span>"),
            std::string::npos);
  EXPECT_NE(s.find("unit_0002 <span class=\"fail\">fail: gyro_x (N)</span>"), std::string::npos);
  EXPECT_NE(s.find("lost_unit"), std::string::npos);  // a failed input of the lot summary
  // Without spec columns (the analysed lot's own summary): no colouring.
  report(results().string() + " -q -o " + (d / "plain.html").string());
  const std::string plain = read_file(d / "plain.html");
  EXPECT_EQ(plain.find("class=\"pass\""), std::string::npos);
  EXPECT_EQ(plain.find("class=\"fail\""), std::string::npos);
}

// The lot's header counts units, not channels (a unit passes when every channel a rule covers
// passes, fails when any fails: spec::judge_units), as the terminal overview does; each verdict
// quotes the measured value in the unit the spec wrote its limit in.
TEST_F(Report, CountsUnitsAgainstTheSpecAndQuotesTheSpecsUnits) {
  const fs::path d = test::fresh_dir("report_units_verdict");
  for (const auto& e : fs::directory_iterator(results()))
    if (e.path().filename().string().ends_with(".allan.h5"))
      fs::copy_file(e.path(), d / e.path().filename());
  // gyro N = 0.005 deg/s*s^0.5 = 0.3 deg/sqrt(h) (5 % spread) passes 0.6; odd_unit's 0.03 =
  // 1.8 deg/sqrt(h) fails (it has no accelerometer); accel N = 0.002 m/s^2*s^0.5 =
  // 0.12 m/s/sqrt(h) passes 1. Channels: 10 pass, 1 fail; units: 5 pass, 1 fail.
  {
    std::ofstream spec(d / "spec.json");
    spec << R"j({"channels": {"gyro_*": {"N": {"max": 0.6, "unit": "deg/sqrt(h)"}},
                              "accel_*": {"N": {"max": 1, "unit": "m/s/sqrt(h)"}}}})j";
  }
  std::string out;
  ASSERT_EQ(
      run_command(binary() + " summarize --spec " + (d / "spec.json").string() + " " + d.string(),
                  &out),
      0)
      << out;
  EXPECT_NE(out.find("units: 5 pass, 1 fail, 0 undecided"), std::string::npos) << out;
  report(d.string() + " -q");
  const std::string s = read_file(d / "report.html");
  EXPECT_NE(s.find("<b>Units against the spec:</b> <span class=\"pass\">5 pass</span> <span "
                   "class=\"fail\">1 fail</span> <span class=\"undecided\">0 undecided</span>"),
            std::string::npos);
  EXPECT_EQ(s.find("10 pass"), std::string::npos);
  // The verdicts in the spec's units, each term on its own line: ARW in deg/sqrt(h) beside its
  // limit (not deg/h/sqrt(Hz), the table's column), VRW in m/s/sqrt(h).
  const std::regex gyro("<td class=\"verdict pass\"><b>pass</b>: <span class=\"term\">N "
                        "0\\.[23][0-9]*±[0-9.e-]+ &lt;= 0\\.6 deg/sqrt\\(h\\)</span></td>");
  const std::regex accel("<td class=\"verdict pass\"><b>pass</b>: <span class=\"term\">N "
                         "0\\.1[0-9]*±[0-9.e-]+ &lt;= 1 m/s/sqrt\\(h\\)</span></td>");
  const std::regex odd("<td class=\"verdict fail\"><b>fail</b>: <span class=\"term\">N "
                       "1\\.[6-9][0-9]*±[0-9.e-]+ &gt; 0\\.6 deg/sqrt\\(h\\)</span></td>");
  const auto n_matches = [&](const std::regex& r) {
    return std::distance(std::sregex_iterator(s.begin(), s.end(), r), std::sregex_iterator());
  };
  EXPECT_EQ(n_matches(gyro), 5);
  EXPECT_EQ(n_matches(accel), 5);
  EXPECT_EQ(n_matches(odd), 1);
  // The unit page's verdict line quotes the same.
  EXPECT_NE(s.find("spec: <span class=\"fail\">fail: N 1."), std::string::npos);
}

// The distribution plots print each term's lot median with its unit, and name their axes.
TEST_F(Report, DistributionPlotsCarryUnits) {
  report(results().string() + " -q -o " + (dir() / "dist.html").string());
  const std::string s = read_file(dir() / "dist.html");
  const auto plot = [&](const std::string& id) {
    const auto at = s.find("id=\"" + id + "\"");
    return at == std::string::npos ? std::string() : s.substr(at, s.find("</svg>", at) - at);
  };
  const std::string gyro = plot("dist-_imu_gyro_x"), accel = plot("dist-_imu_accel_x");
  ASSERT_FALSE(gyro.empty());
  ASSERT_FALSE(accel.empty());
  // Term, median, unit: three lines under each detected term.
  EXPECT_TRUE(std::regex_search(gyro, std::regex(">N<tspan[^>]*>[0-9.]+</tspan><tspan[^>]*>"
                                                 "deg/h/sqrt\\(Hz\\)</tspan></text>")))
      << gyro;
  EXPECT_TRUE(std::regex_search(accel, std::regex(">N<tspan[^>]*>[0-9.]+</tspan><tspan[^>]*>"
                                                  "mg/sqrt\\(Hz\\)</tspan></text>")));
  for (const std::string* p : {&gyro, &accel}) {
    EXPECT_NE(p->find(">value / lot median (ratio)</text>"), std::string::npos);
    EXPECT_NE(p->find(">term, lot median and its unit</text>"), std::string::npos);
  }
}

// Table cells never break inside a number, a unit or a name (tests/browser/check_report.py
// measures it in Chromium): no break-anywhere rule, data cells that do not wrap, and numbers
// without an exponent from 1 to a million (%g's "1.3e+02" for 130).
TEST_F(Report, TableCellsKeepTheirTokensWhole) {
  report(results().string() + " -q -o " + (dir() / "cells.html").string());
  const std::string s = read_file(dir() / "cells.html");
  EXPECT_EQ(s.find("overflow-wrap:anywhere"), std::string::npos);
  EXPECT_NE(s.find("td{white-space:nowrap}"), std::string::npos);
  EXPECT_NE(s.find("<div class=\"scroll\"><h3 id=\"lot-_imu_gyro_x\">"), std::string::npos);
  // A status is words ("ok (fit: poor fit (chi2/dof = 709))"): it wraps between them.
  EXPECT_NE(s.find("td.words{white-space:normal"), std::string::npos);
  EXPECT_NE(s.find("<td class=\"l words\">ok"), std::string::npos);
  std::smatch m;
  EXPECT_FALSE(std::regex_search(s, m, std::regex("<td[^>]*>[^<]*[0-9]e\\+0[0-5][^<]*</td>")))
      << m.str();
}

TEST_F(Report, ClearErrors) {
  const fs::path d = test::fresh_dir("report_errors");
  // Not a directory.
  std::string out = report((d / "missing").string(), 2);
  EXPECT_NE(out.find((d / "missing").string() + ": not a directory"), std::string::npos) << out;
  // No results files.
  out = report(d.string(), 2);
  EXPECT_NE(out.find("no results files"), std::string::npos) << out;
  // One unreadable results file among good ones: written for the rest, exit 1, named.
  for (const char* u : {"unit_0001.allan.h5", "unit_0002.allan.h5"})
    fs::copy_file(results() / u, d / u);
  {
    std::ofstream bad(d / "broken.allan.h5");
    bad << "not HDF5";
  }
  out = report(d.string() + " -o " + (d / "r.html").string(), 1);
  EXPECT_NE(out.find("broken.allan.h5"), std::string::npos) << out;
  const std::string s = read_file(d / "r.html");
  EXPECT_NE(s.find("id=\"u-unit_0002\""), std::string::npos);
  EXPECT_NE(s.find("broken.allan.h5"), std::string::npos);  // listed under Problems
  // Unwritable output: usage error naming the file; nothing half-written.
  const fs::path unwritable = d / "no" / "such" / "dir" / "r.html";
  out = report(d.string() + " -o " + unwritable.string(), 2);
  EXPECT_NE(out.find(unwritable.string()), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(unwritable));
  // Unknown option value.
  report(d.string() + " --unit-pages sometimes", 2);
}

}  // namespace
}  // namespace allanlot
