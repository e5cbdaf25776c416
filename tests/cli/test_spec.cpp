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
  // converted to the row's unit before comparing, and the detail quotes the estimate in the
  // limit's own unit: 18.3 deg/h/sqrt(Hz) = 18.3 / 60 deg/sqrt(h), k sigma = 1.96 * 0.02 / 60.
  const auto sp = parse(
      R"j({"confidence": 0.95, "channels": {"gyro_*": {
        "N": {"max": 0.3, "unit": "deg/sqrt(h)"}, "B": {"max": 10, "unit": "deg/h"}}}})j");
  const double k = sp.k;
  // N interval [18.3 - k 0.02, 18.3 + k 0.02] lies above 18: fail, whatever B does.
  auto v = spec::judge(sp, gyro_row(18.3, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "fail");
  EXPECT_EQ(v.detail, "N 0.305±0.00065 > 0.3 deg/sqrt(h)");
  EXPECT_EQ(v.term_status, (std::array<std::string, 5>{"", "", "pass", "fail", ""}));
  // Straddling 18: undecided.
  v = spec::judge(sp, gyro_row(17.99, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "undecided");
  EXPECT_NE(v.detail.find("N 0.3±0.00065 ~ 0.3 deg/sqrt(h)"), std::string::npos) << v.detail;
  // Both well inside: pass, and the detail lists both terms.
  v = spec::judge(sp, gyro_row(17.0, 0.02, 4.5, 0.1));
  EXPECT_EQ(v.status, "pass");
  EXPECT_EQ(v.detail, "N 0.283±0.00065 <= 0.3 deg/sqrt(h); B 4.5±0.2 <= 10 deg/h");
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

TEST(Spec, DetailQuotesTheEstimateInTheUnitOfItsLimit) {
  // The same row and the same limit (0.3 deg/sqrt(h) = 18 deg/h/sqrt(Hz)) written in either
  // datasheet form, or as a spelling of it: the decision is the same, and the detail quotes the
  // estimate beside the limit in the form the spec used (one normalized spelling).
  const auto row = gyro_row(18.3, 0.02, 4.5, 0.1);
  const auto in = [&](const std::string& n_limit) {
    return spec::judge(parse(R"j({"channels": {"gyro_*": {"N": )j" + n_limit + "}}}"), row);
  };
  const auto arw = in(R"j({"max": 0.3, "unit": "deg/sqrt(h)"})j");
  const auto density = in(R"j({"max": 18, "unit": "deg/h/sqrt(Hz)"})j");
  const auto spelled = in(R"j({"max": 0.3, "unit": "°/√hr"})j");
  const auto own = in(R"j({"max": 0.005, "unit": "deg/s*s^0.5"})j");
  EXPECT_EQ(arw.detail, "N 0.305±0.00065 > 0.3 deg/sqrt(h)");
  EXPECT_EQ(density.detail, "N 18.3±0.039 > 18 deg/h/sqrt(Hz)");
  EXPECT_EQ(spelled.detail, arw.detail);
  // 18.3 / 3600 = 0.0050833 deg/s*s^0.5 (units.hpp: deg/h/sqrt(Hz) = 3600 deg/s*s^0.5).
  EXPECT_EQ(own.detail, "N 0.00508±1.1e-05 > 0.005 deg/s*s^0.5");
  for (const auto* v : {&arw, &density, &spelled, &own}) {
    EXPECT_EQ(v->status, "fail");
    EXPECT_EQ(v->term_status, arw.term_status);
  }
  // An undetected term's bound is quoted in the limit's unit too: 12 deg/h = 12 / 3600 deg/s.
  auto undetected = gyro_row(17.0, 0.02, 0.0, 3.0);
  undetected.detected[2] = 0;
  undetected.upper[2] = 12.0;
  EXPECT_EQ(
      spec::judge(parse(R"j({"channels": {"gyro_*": {"B": {"max": 0.0025, "unit": "deg/s"}}}})j"),
                  undetected)
          .detail,
      "B <0.00333 ~ 0.0025 deg/s");
}

// A term is never passed or failed from a curve its model does not describe
// (docs/fit-and-psd.md "When eq. (3) is a poor fit"): a row whose fit is not within noise (a
// poor eq. (3) fit whose model is still beyond noise, or that was not modelled) leaves every
// limited term undecided, whichever side of its limit the estimate lies; within noise, or
// unknown (an earlier version's row), it is judged on its interval alone.
TEST(Spec, FitNotWithinNoiseLeavesEveryTermUndecided) {
  const auto sp = parse(
      R"j({"confidence": 0.95, "channels": {"gyro_*": {
        "N": {"max": 18, "unit": "deg/h/sqrt(Hz)"}, "B": {"max": 10, "unit": "deg/h"}}}})j");
  for (const auto& [n, verdict] : {std::pair{17.0, "pass"}, {19.0, "fail"}}) {
    auto row = gyro_row(n, 0.02, 4.5, 0.1);
    EXPECT_EQ(spec::judge(sp, row).status, verdict);  // fit_within_noise -1: unknown
    row.fit_within_noise = 1;
    EXPECT_EQ(spec::judge(sp, row).status, verdict);
    row.fit_within_noise = 0;
    const spec::Verdict v = spec::judge(sp, row);
    EXPECT_EQ(v.status, "undecided") << v.detail;
    EXPECT_EQ(v.term_status, (std::array<std::string, 5>{"", "", "undecided", "undecided", ""}));
    EXPECT_NE(v.detail.find("(fit not within noise)"), std::string::npos) << v.detail;
  }
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

// Each datasheet form of the units vocabulary (kernels/model/units.hpp) in a spec: accepted by
// the parser, and its limit converted to the channel's own units by the known factor (1 h =
// 3600 s, sqrt(h) = 60 sqrt(s), g = 9.80665 m/s^2, 1 deg = pi/180 rad), in the spellings
// datasheets print.
TEST(Spec, EveryDatasheetFormIsAcceptedAndConvertedRight) {
  const double g = 9.80665, deg = 180.0 / 3.14159265358979323846;
  const struct {
    Term term;
    const char* channel_units;
    const char* unit;
    double limit;
    double expected;  // in the channel's own units and seconds
  } cases[] = {
      {Term::N, "deg/s", "deg/sqrt(h)", 0.3, 0.005},       // ARW: 0.3 / 60
      {Term::N, "deg/s", "deg/√hr", 0.3, 0.005},           // the same, as printed
      {Term::N, "deg/s", "deg/h/sqrt(Hz)", 18, 0.005},     // 18 / 3600
      {Term::N, "deg/s", "°/hr/√Hz", 18, 0.005},           // the same, as printed
      {Term::N, "deg/s", "deg/s/sqrt(Hz)", 0.005, 0.005},  // the channel's own
      {Term::N, "deg/s", "rad/s/sqrt(Hz)", 1e-4, 1e-4 * deg},
      {Term::N, "deg/h", "deg/sqrt(h)", 0.3, 18},  // a deg/h channel: 0.3 * 60
      {Term::B, "deg/s", "deg/h", 36, 0.01},
      {Term::B, "deg/s", "deg/hr", 36, 0.01},
      {Term::B, "deg/s", "rad/s", 1e-5, 1e-5 * deg},
      {Term::K, "deg/s", "deg/h/sqrt(h)", 2.16, 1e-5},  // 2.16 / (3600 * 60)
      {Term::R, "deg/s", "deg/h/h", 12.96, 1e-6},       // 12.96 / 3600^2
      {Term::Q, "deg/s", "urad", 17.453292519943296, 1e-3},
      {Term::Q, "deg/s", "arcsec", 3.6, 1e-3},
      {Term::N, "m/s^2", "mg/sqrt(Hz)", 0.1, 1e-4 * g},
      {Term::N, "m/s^2", "ug/sqrt(Hz)", 100, 1e-4 * g},
      {Term::N, "m/s^2", "µg/√Hz", 100, 1e-4 * g},
      {Term::N, "m/s^2", "g/sqrt(Hz)", 1e-4, 1e-4 * g},
      {Term::N, "m/s^2", "m/s/sqrt(h)", 0.06, 0.001},  // VRW: 0.06 / 60
      {Term::N, "m/s^2", "m/s^2/sqrt(Hz)", 1e-3, 1e-3},
      {Term::B, "m/s^2", "mg", 0.05, 5e-5 * g},
      {Term::B, "m/s^2", "ug", 50, 5e-5 * g},
      {Term::K, "m/s^2", "mg/sqrt(h)", 0.6, 1e-5 * g},  // 0.6 / 60 mg/sqrt(s)
  };
  for (const auto& c : cases) {
    const std::string term(kernels::units::term_name(c.term));
    const std::string json = R"j({"channels": {"x": {")j" + term + R"j(": {"max": )j" +
                             std::to_string(c.limit) + R"j(, "unit": ")j" + c.unit + "\"}}}}";
    spec::Spec sp;
    ASSERT_NO_THROW(sp = parse(json)) << json;
    ASSERT_EQ(sp.rules[0].limits.size(), 1u);
    EXPECT_EQ(sp.rules[0].limits[0].unit, c.unit);
    const std::string own = kernels::units::channel_unit(c.term, c.channel_units);
    EXPECT_NEAR(spec::convert(c.term, c.limit, c.unit, own, c.channel_units), c.expected,
                1e-12 * c.expected)
        << term << " " << c.unit << " for a " << c.channel_units << " channel";
  }
}

// Every unit the vocabulary accepts for a term of a gyro or an accelerometer is accepted in a
// spec, and a limit in it converts to a finite positive value in the channel's units (the
// values themselves: EveryDatasheetFormIsAcceptedAndConvertedRight).
TEST(Spec, EveryAcceptedUnitOfTheVocabularyIsAcceptedInASpec) {
  std::size_t n = 0;
  for (const char* channel_units : {"deg/s", "m/s^2"})
    for (const Term t : {Term::R, Term::K, Term::B, Term::N, Term::Q}) {
      const std::string term(kernels::units::term_name(t));
      const std::string own = kernels::units::channel_unit(t, channel_units);
      for (const std::string& unit : kernels::units::accepted_units(t, channel_units)) {
        const std::string json =
            R"j({"channels": {"x": {")j" + term + R"j(": {"max": 2, "unit": ")j" + unit + "\"}}}}";
        EXPECT_NO_THROW(parse(json)) << json;
        const double v = spec::convert(t, 2.0, unit, own, channel_units);
        EXPECT_TRUE(std::isfinite(v) && v > 0) << term << " " << unit << " -> " << v;
        ++n;
      }
    }
  EXPECT_GE(n, 40u);  // the vocabulary's forms (units.cpp), not an empty loop
}

// One run names every problem of a spec, in file order, each with the file and its key path.
TEST(Spec, EveryErrorIsReportedAtOnce) {
  const std::string json = R"j({
    "colour": "red",
    "confidence": 2,
    "channels": {
      "gyro_*": {"N": {"max": -1, "unit": "furlongs"},
                 "B": {"min": 5, "max": 1, "unit": "deg/h"},
                 "X": {"max": 1, "unit": "deg/h"}},
      "[accel": {"N": {"max": 0.05, "unit": "mg/sqrt(Hz)"}},
      "mag_*": {"quality": {"max_spikes": -3, "sparkle": "fail"}}
    }})j";
  try {
    parse(json);
    FAIL() << "accepted";
  } catch (const spec::Error& e) {
    const std::vector<std::string> expected = {
        "spec.json: colour: unknown key",
        "spec.json: confidence: must be in (0, 1), got 2",
        "spec.json: channels.gyro_*.N.max: must be >= 0, got -1",
        "spec.json: channels.gyro_*.N.unit: 'furlongs' is not a unit of N",
        "spec.json: channels.gyro_*.B.min: must not exceed max (1), got 5",
        "spec.json: channels.gyro_*.X: unknown key",
        "spec.json: channels.[accel: unknown channel pattern",
        "spec.json: channels.mag_*.quality.max_spikes: must be an integer >= 0, got -3",
        "spec.json: channels.mag_*.quality.sparkle: unknown key",
    };
    ASSERT_EQ(e.messages().size(), expected.size()) << e.what();
    for (std::size_t i = 0; i < expected.size(); ++i)
      EXPECT_EQ(e.messages()[i].rfind(expected[i], 0), 0u) << e.messages()[i];
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("spec.json: 9 errors:\n  spec.json: colour: unknown key\n", 0), 0u)
        << what;
    for (const auto& m : e.messages())
      EXPECT_NE(what.find("\n  " + m), std::string::npos) << m;
  }
  // One problem alone is the one message, as before.
  try {
    parse(R"j({"channels": {"g": {"N": {"max": -1, "unit": "deg/h/sqrt(Hz)"}}}})j");
    FAIL() << "accepted";
  } catch (const spec::Error& e) {
    EXPECT_EQ(std::string(e.what()), "spec.json: channels.g.N.max: must be >= 0, got -1");
    EXPECT_EQ(e.messages().size(), 1u);
  }
  // Bracket expressions that close are patterns like any other.
  EXPECT_NO_THROW(parse(R"j({"channels": {"gyro_[xy]": {"B": {"max": 1, "unit": "deg/h"}},
                                          "[]x]*": {"B": {"max": 1, "unit": "deg/h"}}}})j"));
}

// The unit's verdict: pass only when every channel with a rule passes; otherwise which channel
// (and term) made it fail or stay undecided.
TEST(Spec, UnitVerdictPassesOnlyWhenEveryChannelPasses) {
  const auto sp = parse(R"j({"channels": {"gyro_*": {"N": {"max": 18.5, "unit":
                            "deg/h/sqrt(Hz)"}, "B": {"max": 5, "unit": "deg/h"}}}})j");
  std::vector<io::SummaryRow> rows;
  const auto add = [&](const std::string& dev, const std::string& chan, double n, double b) {
    auto r = gyro_row(n, 0.01, b, 0.01);
    r.device_id = dev;
    r.channel = chan;
    rows.push_back(r);
  };
  add("A", "/imu/gyro_x", 18, 4);    // pass
  add("A", "/imu/gyro_y", 18, 4);    // pass
  add("A", "/imu/mag_x", 99, 99);    // no rule: does not count
  add("B", "/imu/gyro_x", 18, 4);    // pass
  add("B", "/imu/gyro_y", 19, 6);    // fail on N and B
  add("B", "/imu/gyro_z", 18.5, 4);  // undecided on N: 18.5 +- 0.0196 straddles 18.5
  add("C", "/imu/gyro_x", 18, 4);
  add("C", "/imu/gyro_y", 18.5, 4);  // undecided
  add("D", "/imu/gyro_x", 18, 4);
  rows.back().status = io::ChannelStatus::failed("too short");  // no data: cannot pass
  add("D", "/imu/gyro_y", 18, 4);
  add("E", "/imu/mag_x", 1, 1);  // nothing covered
  for (auto& r : rows) {
    const auto v = spec::judge(sp, r);
    r.spec_status = v.status;
    r.spec_term_status = v.term_status;
  }
  spec::judge_units(rows);
  const auto unit = [&](const std::string& dev) {
    for (const auto& r : rows)
      if (r.device_id == dev) return std::make_pair(r.unit_spec_status, r.unit_spec_detail);
    return std::make_pair(std::string("?"), std::string("?"));
  };
  EXPECT_EQ(unit("A"), std::make_pair(std::string("pass"), std::string()));
  EXPECT_EQ(unit("B"), std::make_pair(std::string("fail"),
                                      std::string("fail: gyro_y (B, N); undecided: gyro_z (N)")));
  EXPECT_EQ(unit("C"),
            std::make_pair(std::string("undecided"), std::string("undecided: gyro_y (N)")));
  EXPECT_EQ(unit("D"), std::make_pair(std::string("undecided"), std::string("no data: gyro_x")));
  EXPECT_EQ(unit("E"), std::make_pair(std::string("no spec"), std::string()));
  for (const auto& r : rows)  // the same on every row of a unit
    EXPECT_EQ(r.unit_spec_status, unit(r.device_id).first) << r.device_id << r.channel;
  // Without a spec the columns stay empty.
  std::vector<io::SummaryRow> plain{gyro_row(18, 0.01, 4, 0.01)};
  spec::judge_units(plain);
  EXPECT_EQ(plain[0].unit_spec_status, "");
}

}  // namespace
}  // namespace allanlot
