// The one audited conversion between the noise coefficients in a channel's own units and the
// units datasheets print them in.
//
// Coefficients are stored in the channel's units u and seconds (docs/formats.md "Units
// and conventions"): R [u/s], K [u/s^0.5], B [u], N [u*s^0.5], Q [u*s]. Datasheets print them per
// hour and per sqrt(hour) (gyros) or in mg (accelerometers). Every factor below is a product
// of exact unit relations; none is a fitted or rounded number:
//
//   1 h = 3600 s,  sqrt(1 h) = 60 sqrt(s),  1 Hz = 1/s,  1 deg = pi/180 rad,
//   1 g = 9.80665 m/s^2 (standard gravity, CGPM 1901),  1 mg = 1e-3 g.
//
// Hence, for a gyro with u = deg/s:
//   B  deg/s                 * 3600        = deg/h
//   N  deg/s*s^0.5 = deg/sqrt(s) * 60     = deg/sqrt(h)        (ARW)
//      deg/s*s^0.5 = deg/s/sqrt(Hz) * 3600 = deg/h/sqrt(Hz)    (rate noise density)
//   K  deg/s/s^0.5           * 3600 * 60   = deg/h/sqrt(h)
//   R  deg/s/s               * 3600^2      = deg/h/h
//   Q  deg/s*s = deg         * pi/180 * 1e6 = urad  (and deg)
// so 0.3 deg/sqrt(h) = 0.005 deg/sqrt(s) = 18 deg/h/sqrt(Hz), the ADIS16488 pair. For an
// accelerometer with u = m/s^2:
//   B  m/s^2                 * 1000/g      = mg
//   N  m/s^2*s^0.5 = m/s/sqrt(s) * 60     = m/s/sqrt(h)        (VRW)
//      m/s^2*s^0.5 = m/s^2/sqrt(Hz) * 1000/g = mg/sqrt(Hz)
//   K  m/s^2/s^0.5           * 1000/g * 60 = mg/sqrt(h)
//   R  m/s^2/s               * 1000/g * 3600 = mg/h
//   Q  m/s^2*s               * 1           = m/s
// Channels in deg/h, rad/s, g or mg are first scaled to deg/s or m/s^2. Clocks (units `s`,
// a time-error phase whose rate is dimensionless, and `1`, fractional frequency) and any other
// unit string keep their own units, composed as in docs/formats.md.
#pragma once

#include "kernels/model/terms.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels::units {

// The terms and their names are kernels/model/terms.hpp's; units:: spells them too.
using kernels::all_terms;
using kernels::parse_term;
using kernels::Term;
using kernels::term_name;

/// A unit as written (a CSV header, an HDF5 attribute, a spec, a datasheet), spelled as allanlot
/// does: no blanks; the degree sign as deg, micro (µ or μ) as u, the square-root sign as sqrt,
/// ² as ^2; each '/'-separated piece in one spelling (sec/second(s) → s, hr/hour(s) → h,
/// degree(s) → deg, rtHz/√Hz/Hz^0.5/Hz^(1/2) → sqrt(Hz), √h/sqrt(hr) → sqrt(h), s2 → s^2).
/// "deg/sec" → "deg/s", "°/hr/√Hz" → "deg/h/sqrt(Hz)", "µg/√Hz" → "ug/sqrt(Hz)".
std::string normalize_spelling(std::string_view spelled);

/// A channel's unit in the vocabulary: the canonical unit and the factor from the unit as
/// written to it (1 but for the clock units below).
struct ChannelUnits {
  std::string canonical;
  double scale = 1;
  /// A clock's frequency in Hz: fractional frequency only with the oscillator's nominal
  /// frequency F, y = (f - F) / F (SP1065 sec. 3; to_fractional_frequency).
  bool per_nominal = false;
};
/// The channel units allanlot knows, in any spelling normalize_spelling reduces to one of:
/// gyros deg/s (dps, °/s, deg/sec), deg/h (dph, °/hr), rad/s; accelerometers m/s^2 (m/s2,
/// m/s/s, m/s²), g, mg (milli-g), ug (µg, μg); clocks s (time error; also ms, us, ns, ps,
/// scaled to s) and 1 (fractional frequency; also ppm, ppb, ppt, scaled to 1, and Hz, a
/// frequency made fractional with the nominal frequency: per_nominal). nullopt for any other
/// string.
std::optional<ChannelUnits> parse_channel_units(std::string_view spelled);

/// A frequency f in Hz as fractional frequency, y = (f - F) / F for the nominal frequency
/// F > 0. f - F is exact for F/2 <= f <= 2F (Sterbenz), so y keeps every digit the recording
/// has; f / F - 1 would keep only 16 - |log10 y| of them.
inline double to_fractional_frequency(double f_hz, double nominal_hz) {
  return (f_hz - nominal_hz) / nominal_hz;
}

/// What kind of sensor a channel unit string denotes.
enum class Family {
  Gyro,           // deg/s, deg/h, rad/s
  Accelerometer,  // m/s^2, g, mg, ug
  Clock,          // s (time error; its rate is dimensionless), 1 (fractional frequency)
  Other           // anything else: kept as it is
};
Family family_of(std::string_view channel_units);

/// A value with its unit string.
struct Quantity {
  double value = 0;
  std::string unit;
};

/// A coefficient as a datasheet prints it: the primary form (the paper's Table: N in
/// deg/h/sqrt(Hz) and mg/sqrt(Hz)) and, where datasheets commonly use two (N also as the
/// random walk deg/sqrt(h) or m/s/sqrt(h); Q as urad and deg), the secondary form.
struct Datasheet {
  Quantity primary;
  std::optional<Quantity> secondary;
};

/// The coefficient's unit in channel units and seconds, e.g. "deg/s*s^0.5" for N of a deg/s
/// channel, "m/s^2/s^0.5" for K of an m/s^2 channel, "s^0.5" for N of a clock.
std::string channel_unit(Term t, std::string_view channel_units);

/// Converts a coefficient in channel units (as stored) to its datasheet forms. For clocks and
/// unknown units the primary form is the value itself in channel_unit(t, channel_units).
Datasheet to_datasheet(Term t, double value, std::string_view channel_units);

/// A coefficient in channel units (as stored) in SI: gyros in rad/s and seconds ("rad/s*s^0.5"
/// for N, the continuous-time noise density rad/s/sqrt(Hz)), accelerometers in m/s^2 and
/// seconds, as robotics tools (Kalibr, OpenVINS) take them; clocks and unknown units as they
/// are, in channel_unit(t, channel_units).
Quantity to_si(Term t, double value, std::string_view channel_units);

/// The unit strings from_datasheet accepts for this term and channel: the datasheet forms of
/// to_datasheet, the other forms datasheets use (deg/s/sqrt(Hz) and rad/s/sqrt(Hz) beside
/// deg/h/sqrt(Hz), ug/sqrt(Hz) and m/s^2/sqrt(Hz) beside mg/sqrt(Hz), ug beside mg, rad and
/// arcsec beside urad, ...) and channel_unit(t, channel_units); each in any spelling that
/// normalize_spelling reduces to it.
std::vector<std::string> accepted_units(Term t, std::string_view channel_units);

/// Inverse of to_datasheet: `value` in `unit` (one of accepted_units, in any spelling) to
/// channel units.
/// Throws std::invalid_argument naming the term, the unit and the accepted units otherwise.
double from_datasheet(Term t, double value, std::string_view unit, std::string_view channel_units);

}  // namespace allanlot::kernels::units
