// The units module against hand-derived values and published datasheet pairs, and round trips
// for every unit and term.
#include "kernels/model/units.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace allanlot {
namespace {

using kernels::units::Term;
namespace units = kernels::units;

// The factors are products of exact relations: only a few ulps of rounding.
constexpr double kRel = 1e-14;

double primary(Term t, double v, const char* u) {
  return units::to_datasheet(t, v, u).primary.value;
}
double secondary(Term t, double v, const char* u) {
  const auto d = units::to_datasheet(t, v, u);
  EXPECT_TRUE(d.secondary.has_value());
  return d.secondary ? d.secondary->value : NAN;
}

TEST(Units, Adis16488ArwPair) {
  // ADIS16488 datasheet: ARW 0.3 deg/sqrt(h) = rate noise density 18 deg/h/sqrt(Hz)
  // (0.3 deg/sqrt(h) = 0.3/60 deg/sqrt(s) = 0.005 deg/s/sqrt(Hz) = 18 deg/h/sqrt(Hz)).
  const double n = units::from_datasheet(Term::N, 0.3, "deg/sqrt(h)", "deg/s");
  EXPECT_NEAR(n, 0.005, 0.005 * kRel);
  EXPECT_NEAR(primary(Term::N, n, "deg/s"), 18.0, 18.0 * kRel);  // the paper's Table form
  EXPECT_NEAR(secondary(Term::N, n, "deg/s"), 0.3, 0.3 * kRel);
  EXPECT_NEAR(units::from_datasheet(Term::N, 18.0, "deg/h/sqrt(Hz)", "deg/s"), 0.005, 0.005 * kRel);
}

TEST(Units, PaperTableGyroValues) {
  // The Table's gyro X: N = 18 deg/h/sqrt(Hz), B = 4.5 deg/h, K = 0.1 deg/h/sqrt(h).
  EXPECT_NEAR(units::from_datasheet(Term::B, 4.5, "deg/h", "deg/s"), 0.00125, 0.00125 * kRel);
  // 0.1 / (3600 * 60) = 4.6296e-7 deg/s/sqrt(s)
  EXPECT_NEAR(units::from_datasheet(Term::K, 0.1, "deg/h/sqrt(h)", "deg/s"), 0.1 / 216000, 1e-20);
  EXPECT_NEAR(units::from_datasheet(Term::K, 0.1, "deg/h/sqrt(h)", "deg/s"), 4.63e-7, 0.01e-7);
  // gyro Z: R = 0.02 deg/h/h = 0.02 / 3600^2 deg/s^2
  EXPECT_NEAR(units::from_datasheet(Term::R, 0.02, "deg/h/h", "deg/s"), 0.02 / 12960000.0, 1e-22);
  // The same channel recorded in deg/h: B is then 4.5 deg/h in channel units too.
  EXPECT_NEAR(units::from_datasheet(Term::B, 4.5, "deg/h", "deg/h"), 4.5, 4.5 * kRel);
  // rad/s: 0.005 deg/sqrt(s) = 0.005 pi/180 rad/sqrt(s)
  EXPECT_NEAR(units::from_datasheet(Term::N, 18, "deg/h/sqrt(Hz)", "rad/s"),
              0.005 * std::numbers::pi / 180, 1e-18);
}

TEST(Units, PaperTableAccelerometerValues) {
  // accel X: N = 0.0295 mg/sqrt(Hz) = 0.0295e-3 * 9.80665 m/s^2*sqrt(s) = 2.8930e-4;
  // in m/s/sqrt(h): * 60 = 0.017358.
  const double n = units::from_datasheet(Term::N, 0.0295, "mg/sqrt(Hz)", "m/s^2");
  EXPECT_NEAR(n, 0.0295e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(secondary(Term::N, n, "m/s^2"), 0.0295e-3 * 9.80665 * 60, 1e-16);
  EXPECT_NEAR(secondary(Term::N, n, "m/s^2"), 0.017358, 1e-6);
  EXPECT_EQ(units::to_datasheet(Term::N, n, "m/s^2").secondary->unit, "m/s/sqrt(h)");
  EXPECT_NEAR(primary(Term::N, n, "m/s^2"), 0.0295, 1e-15);  // the paper's Table form
  EXPECT_EQ(units::to_datasheet(Term::N, n, "m/s^2").primary.unit, "mg/sqrt(Hz)");
  // B = 0.0175 mg = 1.7162e-4 m/s^2; K = 0.0071 mg/sqrt(h) = 0.0071e-3 g / 60 per sqrt(s);
  // R = 0.0019 mg/h = 0.0019e-3 g / 3600 per s.
  EXPECT_NEAR(units::from_datasheet(Term::B, 0.0175, "mg", "m/s^2"), 0.0175e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(units::from_datasheet(Term::K, 0.0071, "mg/sqrt(h)", "m/s^2"),
              0.0071e-3 * 9.80665 / 60, 1e-19);
  EXPECT_NEAR(units::from_datasheet(Term::R, 0.0019, "mg/h", "m/s^2"), 0.0019e-3 * 9.80665 / 3600,
              1e-21);
  // A channel in g: 1 mg is 1e-3 of it.
  EXPECT_NEAR(units::from_datasheet(Term::B, 0.0175, "mg", "g"), 0.0175e-3, 1e-18);
  EXPECT_NEAR(units::from_datasheet(Term::B, 0.0175, "mg", "mg"), 0.0175, 1e-16);
  // ADIS16488's VRW 0.029 m/s/sqrt(h) is 0.029/60 m/s^2*sqrt(s) = 0.0493 mg/sqrt(Hz).
  const double vrw = units::from_datasheet(Term::N, 0.029, "m/s/sqrt(h)", "m/s^2");
  EXPECT_NEAR(primary(Term::N, vrw, "m/s^2"), 0.029 / 60 / 9.80665e-3, 1e-15);
}

TEST(Units, QuantizationForms) {
  // Q of a deg/s channel is in deg: 1e-4 deg = 1.745329 urad.
  const auto d = units::to_datasheet(Term::Q, 1e-4, "deg/s");
  EXPECT_EQ(d.primary.unit, "urad");
  EXPECT_NEAR(d.primary.value, 1e-4 * std::numbers::pi / 180 * 1e6, 1e-14);
  ASSERT_TRUE(d.secondary);
  EXPECT_EQ(d.secondary->unit, "deg");
  EXPECT_NEAR(d.secondary->value, 1e-4, 1e-18);
  EXPECT_EQ(units::to_datasheet(Term::Q, 0.01, "m/s^2").primary.unit, "m/s");
}

TEST(Units, ClocksAndUnknownUnitsPassThrough) {
  for (const char* u : {"s", "1", "V", "counts", "m/s^2/Hz"}) {
    for (Term t : units::all_terms()) {
      const auto d = units::to_datasheet(t, 1.2345e-9, u);
      EXPECT_EQ(d.primary.value, 1.2345e-9) << u;
      EXPECT_FALSE(d.secondary.has_value()) << u;
      EXPECT_EQ(d.primary.unit, units::channel_unit(t, u));
      EXPECT_EQ(units::from_datasheet(t, 7.5, d.primary.unit, u), 7.5);
    }
  }
  EXPECT_EQ(units::channel_unit(Term::N, "V"), "V*s^0.5");
  EXPECT_EQ(units::channel_unit(Term::K, "V"), "V/s^0.5");
  EXPECT_EQ(units::channel_unit(Term::R, "V"), "V/s");
  EXPECT_EQ(units::channel_unit(Term::Q, "V"), "V*s");
  EXPECT_EQ(units::channel_unit(Term::B, "V"), "V");
  // A clock's rate (time error per second, or fractional frequency) is dimensionless.
  EXPECT_EQ(units::channel_unit(Term::N, "s"), "s^0.5");
  EXPECT_EQ(units::channel_unit(Term::B, "1"), "1");
  EXPECT_EQ(units::family_of("s"), units::Family::Clock);
  EXPECT_EQ(units::family_of("V"), units::Family::Other);
}

TEST(Units, RoundTripEveryUnitTermAndForm) {
  for (const char* u : {"deg/s", "deg/h", "rad/s", "m/s^2", "g", "mg", "ug", "s", "1", "V"}) {
    for (Term t : units::all_terms()) {
      const double v = 3.217e-5;
      const auto d = units::to_datasheet(t, v, u);
      EXPECT_NEAR(units::from_datasheet(t, d.primary.value, d.primary.unit, u) / v, 1.0, kRel)
          << u << " " << units::term_name(t);
      if (d.secondary) {
        EXPECT_NEAR(units::from_datasheet(t, d.secondary->value, d.secondary->unit, u) / v, 1.0,
                    kRel)
            << u << " " << units::term_name(t);
      }
      // The channel's own unit string is always accepted, as the identity.
      EXPECT_EQ(units::from_datasheet(t, v, units::channel_unit(t, u), u), v);
      for (const auto& a : units::accepted_units(t, u))
        EXPECT_NO_THROW(units::from_datasheet(t, 1.0, a, u)) << a;
    }
  }
}

TEST(Units, ConsistentAcrossChannelUnits) {
  // The same physical coefficient gives the same datasheet value whatever the channel unit.
  for (Term t : units::all_terms()) {
    const double in_deg_s = 1e-3;
    const double ds = primary(t, in_deg_s, "deg/s");
    EXPECT_NEAR(primary(t, in_deg_s * 3600, "deg/h") / ds, 1.0, kRel);
    EXPECT_NEAR(primary(t, in_deg_s * std::numbers::pi / 180, "rad/s") / ds, 1.0, kRel);
    const double in_ms2 = 2e-3;
    const double da = primary(t, in_ms2, "m/s^2");
    EXPECT_NEAR(primary(t, in_ms2 / 9.80665, "g") / da, 1.0, kRel);
    EXPECT_NEAR(primary(t, in_ms2 / 9.80665e-3, "mg") / da, 1.0, kRel);
  }
}

TEST(Units, WrongUnitIsRejectedWithTheAcceptedList) {
  try {
    units::from_datasheet(Term::N, 1.0, "mg/sqrt(Hz)", "deg/s");
    FAIL() << "accepted an accelerometer unit for a gyro";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("deg/sqrt(h)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mg/sqrt(Hz)"), std::string::npos) << msg;
  }
  EXPECT_THROW(units::from_datasheet(Term::B, 1.0, "deg/sqrt(h)", "deg/s"), std::invalid_argument);
  EXPECT_EQ(units::parse_term("K"), Term::K);
  EXPECT_FALSE(units::parse_term("X").has_value());
}

// The one vocabulary: the spellings of IMU logs, datasheets and clock files, each reduced to
// the unit allanlot computes with and the factor into it.
TEST(Units, ChannelUnitSpellings) {
  struct Case {
    const char* spelled;
    const char* canonical;
    double scale;
  };
  for (const Case& c : std::initializer_list<Case>{{"deg/s", "deg/s", 1},
                                                   {"dps", "deg/s", 1},
                                                   {"\xC2\xB0/s", "deg/s", 1},
                                                   {"deg/sec", "deg/s", 1},
                                                   {"deg / s", "deg/s", 1},
                                                   {"degrees/second", "deg/s", 1},
                                                   {"deg/h", "deg/h", 1},
                                                   {"deg/hr", "deg/h", 1},
                                                   {"\xC2\xB0/h", "deg/h", 1},
                                                   {"dph", "deg/h", 1},
                                                   {"rad/s", "rad/s", 1},
                                                   {"rad/sec", "rad/s", 1},
                                                   {"m/s^2", "m/s^2", 1},
                                                   {"m/s2", "m/s^2", 1},
                                                   {"m/s/s", "m/s^2", 1},
                                                   {"m/s\xC2\xB2", "m/s^2", 1},
                                                   {"g", "g", 1},
                                                   {"mg", "mg", 1},
                                                   {"ug", "ug", 1},
                                                   {"\xC2\xB5g", "ug", 1},
                                                   {"\xCE\xBCg", "ug", 1},
                                                   {"s", "s", 1},
                                                   {"ns", "s", 1e-9},
                                                   {"ps", "s", 1e-12},
                                                   {"1", "1", 1},
                                                   {"ppm", "1", 1e-6},
                                                   {"ppb", "1", 1e-9}}) {
    const auto u = units::parse_channel_units(c.spelled);
    ASSERT_TRUE(u.has_value()) << c.spelled;
    EXPECT_EQ(u->canonical, c.canonical) << c.spelled;
    EXPECT_EQ(u->scale, c.scale) << c.spelled;
    // Canonical units are their own spelling, with no scale.
    EXPECT_EQ(units::parse_channel_units(u->canonical)->canonical, u->canonical);
  }
  for (const char* unknown : {"", "V", "furlong/fortnight", "G", "deg", "m/s", "counts", "LSB"})
    EXPECT_FALSE(units::parse_channel_units(unknown).has_value()) << unknown;
  EXPECT_EQ(units::family_of("ug"), units::Family::Accelerometer);
}

TEST(Units, DatasheetSpellingsAndForms) {
  // ARW: 0.3 deg/sqrt(h) = 0.005 deg/sqrt(s) (units.hpp), however it is written.
  for (const char* arw : {"deg/sqrt(h)", "deg/\xE2\x88\x9Ah", "\xC2\xB0/\xE2\x88\x9Ahr",
                          "deg/sqrt(hr)", "deg/rt(h)", "deg/h^0.5", "deg/hr^(1/2)"})
    EXPECT_NEAR(units::from_datasheet(Term::N, 0.3, arw, "deg/s") / 0.005, 1.0, kRel) << arw;
  // The same N as a rate density: 18 deg/h/sqrt(Hz) = 0.005 deg/s/sqrt(Hz).
  for (const char* d :
       {"deg/h/sqrt(Hz)", "deg/hr/rtHz", "\xC2\xB0/h/\xE2\x88\x9AHz", "deg/hr/Hz^0.5"})
    EXPECT_NEAR(units::from_datasheet(Term::N, 18.0, d, "deg/s") / 0.005, 1.0, kRel) << d;
  EXPECT_NEAR(units::from_datasheet(Term::N, 0.005, "deg/s/\xE2\x88\x9AHz", "deg/s"), 0.005, 1e-18);
  EXPECT_NEAR(
      units::from_datasheet(Term::N, 0.005 * std::numbers::pi / 180, "rad/s/sqrt(Hz)", "deg/s") /
          0.005,
      1.0, kRel);
  // Accelerometers: 1000 ug = 1 mg, in any micro sign; m/s^2/sqrt(Hz) is the channel's own N.
  for (const char* ug : {"ug/sqrt(Hz)", "\xC2\xB5g/\xE2\x88\x9AHz", "\xCE\xBCg/rtHz"})
    EXPECT_NEAR(units::from_datasheet(Term::N, 1000.0, ug, "m/s^2") /
                    units::from_datasheet(Term::N, 1.0, "mg/sqrt(Hz)", "m/s^2"),
                1.0, kRel)
        << ug;
  EXPECT_NEAR(units::from_datasheet(Term::B, 50.0, "ug", "mg"), 0.05, 1e-15);
  EXPECT_NEAR(units::from_datasheet(Term::B, 1.0, "g", "m/s^2"), 9.80665, 1e-12);
  // Quantization: 1 rad = 180/pi deg = 206264.8 arcsec.
  EXPECT_NEAR(units::from_datasheet(Term::Q, 1.0, "rad", "deg/s"), 180 / std::numbers::pi, 1e-12);
  EXPECT_NEAR(units::from_datasheet(Term::Q, 3600.0, "arcsec", "deg/s"), 1.0, 1e-12);
  // A ug channel's datasheet form is mg: 1 ug = 1e-3 mg.
  EXPECT_NEAR(primary(Term::B, 1.0, "ug"), 1e-3, 1e-15);
}

// SI forms (to_si, analyze --si, the robotics exports): rad/s and m/s^2 and seconds; a deg/h
// gyro's N of 1 deg/h*s^0.5 is pi/180/3600 rad/s*s^0.5, an mg accelerometer's B of 1 mg is
// 9.80665e-3 m/s^2; clocks pass through.
TEST(Units, SiForms) {
  const auto n = units::to_si(Term::N, 1.0, "deg/h");
  EXPECT_NEAR(n.value, std::numbers::pi / 180 / 3600, 1e-20);
  EXPECT_EQ(n.unit, "rad/s*s^0.5");
  EXPECT_NEAR(units::to_si(Term::N, 2.0, "rad/s").value, 2.0, 1e-15);
  const auto b = units::to_si(Term::B, 1.0, "mg");
  EXPECT_NEAR(b.value, 9.80665e-3, 1e-17);
  EXPECT_EQ(b.unit, "m/s^2");
  EXPECT_EQ(units::to_si(Term::K, 1.0, "g").unit, "m/s^2/s^0.5");
  EXPECT_NEAR(units::to_si(Term::K, 1.0, "g").value, 9.80665, 1e-12);
  const auto clock = units::to_si(Term::N, 3.0, "1");
  EXPECT_EQ(clock.value, 3.0);
  EXPECT_EQ(clock.unit, units::channel_unit(Term::N, "1"));
}

}  // namespace
}  // namespace allanlot
