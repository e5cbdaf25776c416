// Datasheet unit conversions: the factors and their derivations are in units.hpp.
#include "kernels/model/units.hpp"

#include <algorithm>
#include <array>
#include <numbers>
#include <stdexcept>

namespace allanlot::kernels::units {

namespace {

constexpr double kHour = 3600.0;        // s per h
constexpr double kSqrtHour = 60.0;      // sqrt(s) per sqrt(h)
constexpr double kStandardG = 9.80665;  // m/s^2 per g (CGPM 1901)
constexpr double kMgPerMs2 = 1000.0 / kStandardG;
constexpr double kUradPerDeg = std::numbers::pi / 180.0 * 1e6;

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kArcsecPerDeg = 3600.0;

// A datasheet form: multiply the coefficient in the family's base unit (deg/s or m/s^2, times
// the term's power of seconds) by `factor` to get it in `unit`.
struct Form {
  const char* unit;
  double factor;
};
// The primary and secondary forms are the ones to_datasheet writes; `more` are the other forms
// datasheets print, accepted in specs (unit == nullptr ends a list).
struct TermForms {
  Form primary;
  Form secondary;
  std::array<Form, 5> more;
};
constexpr Form kNone{nullptr, 0};

TermForms gyro_forms(Term t) {
  switch (t) {
  case Term::R:
    return {{"deg/h/h", kHour * kHour},
            kNone,
            {{{"deg/h^2", kHour * kHour},
              {"deg/s/s", 1},
              {"deg/s^2", 1},
              {"rad/s/s", kRadPerDeg},
              {"rad/s^2", kRadPerDeg}}}};
  case Term::K:
    return {{"deg/h/sqrt(h)", kHour * kSqrtHour},
            kNone,
            {{{"deg/s/sqrt(s)", 1}, {"rad/s/sqrt(s)", kRadPerDeg}, kNone}}};
  case Term::B:
    return {{"deg/h", kHour}, kNone, {{{"deg/s", 1}, {"rad/s", kRadPerDeg}, kNone}}};
  case Term::N:
    return {{"deg/h/sqrt(Hz)", kHour},
            {"deg/sqrt(h)", kSqrtHour},
            {{{"deg/s/sqrt(Hz)", 1},
              {"deg/sqrt(s)", 1},
              {"rad/s/sqrt(Hz)", kRadPerDeg},
              {"rad/sqrt(s)", kRadPerDeg},
              kNone}}};
  case Term::Q:
    return {{"urad", kUradPerDeg},
            {"deg", 1.0},
            {{{"rad", kRadPerDeg}, {"arcsec", kArcsecPerDeg}, kNone}}};
  }
  throw std::logic_error("units: bad term");
}

TermForms accel_forms(Term t) {
  switch (t) {
  case Term::R:
    return {{"mg/h", kMgPerMs2 * kHour},
            kNone,
            {{{"ug/h", kMgPerMs2 * 1e3 * kHour}, {"m/s^2/s", 1}, {"m/s^3", 1}, kNone}}};
  case Term::K:
    return {{"mg/sqrt(h)", kMgPerMs2 * kSqrtHour},
            kNone,
            {{{"ug/sqrt(h)", kMgPerMs2 * 1e3 * kSqrtHour}, {"m/s^2/sqrt(s)", 1}, kNone}}};
  case Term::B:
    return {{"mg", kMgPerMs2},
            kNone,
            {{{"ug", kMgPerMs2 * 1e3}, {"m/s^2", 1}, {"g", 1 / kStandardG}, kNone}}};
  case Term::N:
    return {{"mg/sqrt(Hz)", kMgPerMs2},
            {"m/s/sqrt(h)", kSqrtHour},
            {{{"ug/sqrt(Hz)", kMgPerMs2 * 1e3},
              {"m/s^2/sqrt(Hz)", 1},
              {"m/s/sqrt(s)", 1},
              {"g/sqrt(Hz)", 1 / kStandardG},
              kNone}}};
  case Term::Q:
    return {{"m/s", 1.0}, kNone, {{{"mm/s", 1e3}, kNone}}};
  }
  throw std::logic_error("units: bad term");
}

// Every form of a term, primary first.
std::vector<Form> all_forms(const TermForms& tf) {
  std::vector<Form> out{tf.primary};
  if (tf.secondary.unit) out.push_back(tf.secondary);
  for (const Form& f : tf.more)
    if (f.unit) out.push_back(f);
  return out;
}

// Factor from the channel's units to its family's base unit (deg/s or m/s^2); 1 otherwise.
double to_base(std::string_view u) {
  if (u == "deg/s" || u == "m/s^2") return 1.0;
  if (u == "deg/h") return 1.0 / kHour;
  if (u == "rad/s") return 180.0 / std::numbers::pi;
  if (u == "g") return kStandardG;
  if (u == "mg") return kStandardG / 1000.0;
  if (u == "ug") return kStandardG / 1e6;
  return 1.0;
}

bool has_forms(Family f) {
  return f == Family::Gyro || f == Family::Accelerometer;
}

TermForms forms(Family f, Term t) {
  return f == Family::Gyro ? gyro_forms(t) : accel_forms(t);
}

}  // namespace

Family family_of(std::string_view u) {
  if (u == "deg/s" || u == "deg/h" || u == "rad/s") return Family::Gyro;
  if (u == "m/s^2" || u == "g" || u == "mg" || u == "ug") return Family::Accelerometer;
  if (u == "s" || u == "1") return Family::Clock;
  return Family::Other;
}

std::string channel_unit(Term t, std::string_view channel_units) {
  if (family_of(channel_units) == Family::Clock) {
    // The rate of a time error in s (or a fractional frequency) is dimensionless: the
    // seconds alone, "1" standing for the unit they divide or that has none.
    const std::string_view sfx = seconds_suffix(t);
    if (sfx.empty()) return "1";
    if (sfx.front() == '*') return std::string(sfx.substr(1));
    std::string unit = "1";
    unit.append(sfx);
    return unit;
  }
  std::string unit(channel_units);
  unit.append(seconds_suffix(t));
  return unit;
}

Quantity to_si(Term t, double value, std::string_view channel_units) {
  const Family f = family_of(channel_units);
  if (f == Family::Gyro)
    return {value * to_base(channel_units) * kRadPerDeg, channel_unit(t, "rad/s")};
  if (f == Family::Accelerometer) return {value * to_base(channel_units), channel_unit(t, "m/s^2")};
  return {value, channel_unit(t, channel_units)};
}

Datasheet to_datasheet(Term t, double value, std::string_view channel_units) {
  const Family f = family_of(channel_units);
  if (!has_forms(f)) return {{value, channel_unit(t, channel_units)}, std::nullopt};
  const double base = value * to_base(channel_units);
  const TermForms tf = forms(f, t);
  Datasheet d{{base * tf.primary.factor, tf.primary.unit}, std::nullopt};
  if (tf.secondary.unit) d.secondary = Quantity{base * tf.secondary.factor, tf.secondary.unit};
  return d;
}

std::vector<std::string> accepted_units(Term t, std::string_view channel_units) {
  std::vector<std::string> out;
  const Family f = family_of(channel_units);
  if (has_forms(f))
    for (const Form& form : all_forms(forms(f, t)))
      out.emplace_back(form.unit);
  const std::string own = channel_unit(t, channel_units);
  if (std::find(out.begin(), out.end(), own) == out.end()) out.push_back(own);
  return out;
}

double from_datasheet(Term t, double value, std::string_view unit, std::string_view channel_units) {
  const std::string spelled = normalize_spelling(unit);
  if (spelled == normalize_spelling(channel_unit(t, channel_units))) return value;
  const Family f = family_of(channel_units);
  if (has_forms(f))
    for (const Form& form : all_forms(forms(f, t)))
      if (spelled == form.unit) return value / form.factor / to_base(channel_units);
  std::string list;
  for (const auto& a : accepted_units(t, channel_units))
    list += (list.empty() ? "" : ", ") + a;
  throw std::invalid_argument("units: " + std::string(term_name(t)) + " of a '" +
                              std::string(channel_units) + "' channel cannot be given in '" +
                              std::string(unit) + "' (accepted: " + list + ")");
}

}  // namespace allanlot::kernels::units
