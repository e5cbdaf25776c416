// The spec file: strict parsing (every message names the file and the key path), unit
// conversion through kernels/model/units.hpp, and the pass / fail / undecided decisions at their
// boundaries.
#include "src/lot/spec.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <limits>

namespace allanlot {
namespace {

using spec::Outcome;
using Term = kernels::units::Term;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A gyro row (deg/s channel) with N and B in their primary datasheet units.
io::SummaryRow gyro_row(double n, double n_sigma, double b, double b_sigma) {
  io::SummaryRow r{"SN1", "/imu/gyro_x", "deg/s", 1000, io::ChannelStatus::ok(), "/data/sn1.h5"};
  r.value[3] = n;
  r.sigma[3] = n_sigma;
  r.unit[3] = "deg/h/sqrt(Hz)";
  r.detected[3] = 1;
  r.value[2] = b;
  r.sigma[2] = b_sigma;
  r.unit[2] = "deg/h";
  r.detected[2] = 1;
  return r;
}

spec::Spec parse(const std::string& text) {
  return spec::parse_spec(text, "spec.json");
}

TEST(Spec, QuantileIsTheTwoSidedNormalQuantile) {
  // Phi(1.959963984540054) = 0.975 and Phi(1) = 0.8413447460685429 (standard tables).
  EXPECT_NEAR(spec::two_sided_normal_quantile(0.95), 1.959963984540054, 1e-9);
  EXPECT_NEAR(spec::two_sided_normal_quantile(2 * 0.8413447460685429 - 1), 1.0, 1e-9);
  EXPECT_THROW(spec::two_sided_normal_quantile(1.0), std::invalid_argument);
  EXPECT_EQ(parse(R"j({"channels": {"*": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)"}}}})j").k,
            spec::two_sided_normal_quantile(0.95));
}

TEST(Spec, ConvertsBetweenDatasheetForms) {
  // 0.3 deg/sqrt(h) = 0.3/60 deg/sqrt(s) = 0.005 deg/s*s^0.5 = 18 deg/h/sqrt(Hz) (ADIS16488).
  EXPECT_NEAR(spec::convert(Term::N, 0.3, "deg/sqrt(h)", "deg/h/sqrt(Hz)", "deg/s"), 18.0, 1e-12);
  EXPECT_NEAR(spec::convert(Term::N, 18.0, "deg/h/sqrt(Hz)", "deg/sqrt(h)", "deg/s"), 0.3, 1e-14);
  EXPECT_NEAR(spec::convert(Term::N, 0.3, "deg/sqrt(h)", "deg/s*s^0.5", "deg/s"), 0.005, 1e-16);
  // The same limit for a channel recorded in deg/h: its datasheet value is the same number.
  EXPECT_NEAR(spec::convert(Term::N, 0.3, "deg/sqrt(h)", "deg/h/sqrt(Hz)", "deg/h"), 18.0, 1e-12);
  EXPECT_NEAR(spec::convert(Term::B, 10.0, "deg/h", "deg/s", "deg/s"), 10.0 / 3600, 1e-18);
  EXPECT_THROW(spec::convert(Term::N, 1.0, "mg", "deg/h/sqrt(Hz)", "deg/s"), std::invalid_argument);
}

TEST(Spec, DecisionBoundaries) {
  const double k = 2.0;
  const spec::Estimate e{17.0, 0.5, kNaN, true};           // interval [16, 18]
  EXPECT_EQ(spec::decide(e, {}, 18.0, k), Outcome::Pass);  // hi == max passes
  EXPECT_EQ(spec::decide(e, {}, std::nextafter(18.0, 0.0), k), Outcome::Undecided);
  EXPECT_EQ(spec::decide(e, {}, 16.0, k), Outcome::Undecided);  // lo == max: not above it
  EXPECT_EQ(spec::decide(e, {}, std::nextafter(16.0, 0.0), k), Outcome::Fail);
  EXPECT_EQ(spec::decide(e, 16.0, {}, k), Outcome::Pass);  // lo == min passes
  EXPECT_EQ(spec::decide(e, std::nextafter(18.0, 99.0), {}, k), Outcome::Fail);
  EXPECT_EQ(spec::decide(e, 17.0, {}, k), Outcome::Undecided);
  EXPECT_EQ(spec::decide(e, 16.0, 18.0, k), Outcome::Pass);
  EXPECT_EQ(spec::decide(e, 16.5, 20.0, k), Outcome::Undecided);
  EXPECT_EQ(spec::decide(e, 16.5, 15.0, k), Outcome::Fail);  // a fail on either side wins
  // The quantile matters: the same estimate at k = 1 passes max 17.5.
  EXPECT_EQ(spec::decide(e, {}, 17.5, 1.0), Outcome::Pass);
  EXPECT_EQ(spec::decide(e, {}, 17.5, k), Outcome::Undecided);
}

TEST(Spec, UndetectedTermUsesItsUpperBound) {
  const spec::Estimate e{0.0, 1.0, 5.0, false};
  EXPECT_EQ(spec::interval(e, 2.0), std::make_pair(0.0, 5.0));
  EXPECT_EQ(spec::decide(e, {}, 5.0, 2.0), Outcome::Pass);
  EXPECT_EQ(spec::decide(e, {}, 4.9, 2.0), Outcome::Undecided);
  EXPECT_EQ(spec::decide(e, {}, 0.0, 2.0), Outcome::Undecided);  // never a fail: may be 0
  EXPECT_EQ(spec::decide(e, 6.0, {}, 2.0), Outcome::Fail);       // surely below a minimum
  // Without the bound, value + k sigma stands in for it.
  EXPECT_EQ(spec::interval({0.5, 1.0, kNaN, false}, 2.0), std::make_pair(0.0, 2.5));
  // No usable sigma: nothing can be decided against a max.
  EXPECT_EQ(spec::decide({17.0, kNaN, kNaN, true}, {}, 1000.0, 2.0), Outcome::Undecided);
}

TEST(Spec, JudgesRowsWithLimitsInEitherDatasheetForm) {
  // The paper's unit has N = 18 deg/h/sqrt(Hz) = 0.3 deg/sqrt(h); a limit given as ARW is
  // converted to the row's unit before comparing.
  const auto sp = parse(
      R"j({"confidence": 0.95, "channels": {"gyro_*": {
        "N": {"max": 0.3, "unit": "deg/sqrt(h)"}, "B": {"max": 10, "unit": "deg/h"}}}})j");
  const double k = sp.k;
  // N interval [18.3 - k 0.02, 18.3 + k 0.02] lies above 18: fail, whatever B does.
  auto v = spec::judge(sp, gyro_row(18.3, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "fail");
  EXPECT_EQ(v.detail, "N 18.3±0.039 > 18 deg/h/sqrt(Hz)");
  EXPECT_EQ(v.term_status, (std::array<std::string, 5>{"", "", "pass", "fail", ""}));
  // Straddling 18: undecided.
  v = spec::judge(sp, gyro_row(17.99, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "undecided");
  EXPECT_NE(v.detail.find("N 18±0.039 ~ 18 deg/h/sqrt(Hz)"), std::string::npos) << v.detail;
  // Both well inside: pass, and the detail lists both terms.
  v = spec::judge(sp, gyro_row(17.0, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "pass");
  EXPECT_EQ(v.detail, "N 17±0.039 <= 18 deg/h/sqrt(Hz); B 4.5±0.2 <= 10 deg/h");
  // The boundary at exactly value + k sigma == limit passes.
  v = spec::judge(sp, gyro_row(18.0 - k * 0.02, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "pass") << v.detail;
  // An undetected B is judged by its upper bound, quoted as such.
  auto row = gyro_row(17.0, 0.02, 0.0, 3.0);
  row.detected[2] = 0;
  row.upper[2] = 12.0;
  v = spec::judge(sp, row);
  EXPECT_EQ(v.status, "undecided");
  EXPECT_EQ(v.detail, "B <12 ~ 10 deg/h");
  // No rule, no data.
  auto accel = gyro_row(1, 0.1, 1, 0.1);
  accel.channel = "/imu/accel_x";
  EXPECT_EQ(spec::judge(sp, accel).status, "no spec");
  auto failed = gyro_row(17, 0.02, 4.5, 0.1);
  failed.status = io::ChannelStatus::failed("too short");
  EXPECT_EQ(spec::judge(sp, failed).status, "no data");
  EXPECT_EQ(spec::judge(sp, io::SummaryRow{"SN9", "", "", 0,
                                           io::ChannelStatus::failed("unreadable"), "x.h5"})
                .status,
            "no data");
  // A limited term without an estimate cannot pass.
  auto no_b = gyro_row(17.0, 0.02, kNaN, kNaN);
  EXPECT_EQ(spec::judge(sp, no_b).status, "undecided");
  EXPECT_EQ(spec::judge(sp, no_b).detail, "B no estimate");
}

TEST(Spec, FirstMatchingRuleWinsOnPathOrName) {
  const auto sp = parse(
      R"j({"channels": {
        "/imu/gyro_z": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)"}},
        "gyro_*": {"N": {"max": 2, "unit": "deg/h/sqrt(Hz)"}},
        "*": {"N": {"max": 3, "unit": "deg/h/sqrt(Hz)"}}}})j");
  EXPECT_EQ(spec::find_rule(sp, "/imu/gyro_z"), &sp.rules[0]);
  EXPECT_EQ(spec::find_rule(sp, "/imu/gyro_x"), &sp.rules[1]);
  EXPECT_EQ(spec::find_rule(sp, "/imu/accel_x"), &sp.rules[2]);
  const auto only = parse(R"j({"channels": {"gyro_?": {"B": {"min": 1, "unit": "deg/h"}}}})j");
  EXPECT_EQ(spec::find_rule(only, "/imu/temp"), nullptr);
  EXPECT_FALSE(only.rules[0].limits[0].max.has_value());
  EXPECT_EQ(*only.rules[0].limits[0].min, 1.0);
}

TEST(Spec, UnitThatDoesNotFitTheChannelIsAnError) {
  // deg/h/sqrt(Hz) is a unit of N, but not for an accelerometer: the error names the file, the
  // key path, the channel and its units.
  const auto sp = parse(R"j({"channels": {"*": {"N": {"max": 18, "unit": "deg/h/sqrt(Hz)"}}}})j");
  auto accel = gyro_row(0.05, 0.001, 0.02, 0.001);
  accel.channel = "/imu/accel_x";
  accel.units = "m/s^2";
  accel.unit[3] = "mg/sqrt(Hz)";
  try {
    spec::judge(sp, accel);
    FAIL() << "no error";
  } catch (const spec::Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("spec.json: channels.*.N.unit: 'deg/h/sqrt(Hz)' is not a unit of N for a "
                      "'m/s^2' channel",
                      0),
              0u)
        << m;
    EXPECT_NE(m.find("/imu/accel_x"), std::string::npos) << m;
    EXPECT_NE(m.find("mg/sqrt(Hz)"), std::string::npos) << m;  // what would be accepted
  }
}

TEST(Spec, BadFilesNameTheFileAndTheKeyPath) {
  const std::string ok_n = R"j("N": {"max": 18, "unit": "deg/h/sqrt(Hz)"})j";
  const struct {
    std::string json;
    std::string where;  // expected "spec.json: <where>: "
  } cases[] = {
      {R"j({"channels": {"gyro_*": {)j" + ok_n + "}}, \"colour\": 1}", "colour"},
      {R"j({"channels": {"gyro_*": {"X": {"max": 1, "unit": "deg/h"}}}})j", "channels.gyro_*.X"},
      {R"j({"channels": {"gyro_*": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)", "typ": 1}}}})j",
       "channels.gyro_*.N.typ"},
      {R"j({"channels": {"gyro_*": {"N": {"max": "18", "unit": "deg/h/sqrt(Hz)"}}}})j",
       "channels.gyro_*.N.max"},
      {R"j({"channels": {"gyro_*": {"N": {"max": -1, "unit": "deg/h/sqrt(Hz)"}}}})j",
       "channels.gyro_*.N.max"},
      {R"j({"channels": {"gyro_*": {"N": {"min": 2, "max": 1, "unit": "deg/h/sqrt(Hz)"}}}})j",
       "channels.gyro_*.N.min"},
      {R"j({"channels": {"gyro_*": {"N": {"max": 18}}}})j", "channels.gyro_*.N.unit"},
      {R"j({"channels": {"gyro_*": {"N": {"max": 18, "unit": 3}}}})j", "channels.gyro_*.N.unit"},
      {R"j({"channels": {"gyro_*": {"N": {"max": 18, "unit": "mg"}}}})j", "channels.gyro_*.N.unit"},
      {R"j({"channels": {"gyro_*": {"N": {"unit": "deg/h/sqrt(Hz)"}}}})j", "channels.gyro_*.N"},
      {R"j({"channels": {"gyro_*": {"N": {"max": 18, "max": 19, "unit": "deg/h/sqrt(Hz)"}}}})j",
       "channels.gyro_*.N.max"},
      {R"j({"channels": {"gyro_*": {)j" + ok_n + "}, \"gyro_*\": {" + ok_n + "}}}",
       "channels.gyro_*"},
      {R"j({"channels": {"gyro_*": {}}})j", "channels.gyro_*"},
      {R"j({"channels": {}})j", "channels"},
      {R"j({"channels": []})j", "channels"},
      {R"j({"confidence": 0.95})j", "channels"},
      {R"j({"confidence": 1.5, "channels": {"gyro_*": {)j" + ok_n + "}}}", "confidence"},
      {R"j({"confidence": "high", "channels": {"gyro_*": {)j" + ok_n + "}}}", "confidence"},
      {R"j({"name": 7, "channels": {"gyro_*": {)j" + ok_n + "}}}", "name"},
      {R"j({"channels": {"gyro_*": [1, 2]}})j", "channels.gyro_*"},
  };
  for (const auto& c : cases) {
    try {
      parse(c.json);
      ADD_FAILURE() << "accepted: " << c.json;
    } catch (const spec::Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("spec.json: " + c.where + ": ", 0), 0u)
          << e.what() << "\n  for " << c.json;
    }
  }
  // A number too large for a double is not a limit, and broken JSON names the file.
  for (const char* bad : {R"j({"channels": {"g": {"N": {"max": 1e999, "unit": "deg/h"}}}})j",
                          R"j({"channels": )j", ""}) {
    try {
      parse(bad);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const spec::Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("spec.json: ", 0), 0u) << e.what();
    }
  }
}

TEST(Spec, LoadNamesTheFile) {
  const auto dir = test::fresh_dir("spec_load");
  try {
    spec::load_spec(dir / "absent.json");
    FAIL() << "no error";
  } catch (const spec::Error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.json: cannot open"), std::string::npos);
  }
  {
    std::ofstream f(dir / "s.json");
    f << R"j({"name": "tactical", "channels": {"gyro_*": {"B": {"max": 1, "unit": "deg/h"}}}})j";
  }
  const auto sp = spec::load_spec(dir / "s.json");
  EXPECT_EQ(sp.name, "tactical");
  EXPECT_EQ(sp.source, (dir / "s.json").string());
  EXPECT_EQ(sp.confidence, 0.95);
}

}  // namespace
}  // namespace allanlot
