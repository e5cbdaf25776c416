// The model file (docs/formats.md "Model file"): parsing with strict validation, writing, the
// embedded demo unit, and lot draws. `simulate` turns a model into recordings, `diagnose`
// compares a recording with it.
//
// Two forms are accepted:
//   single channel: {"units", "sample_rate_hz", "terms", "effects", "offset", "quantum",
//                    "lot_spread"}
//   unit:           {"sample_rate_hz", "channels": {NAME: {"units", "terms", "effects",
//                    "offset", "quantum"}, ...}, "lot_spread"}
// `units` and `sample_rate_hz` are required; `terms` (any of R, K, B, N, Q; missing = 0),
// `effects` (array of {"type": NAME, KEY: value, ...}, one object per effect: each registered
// effect's name and keys are its header's in kernels/model/effects/, read and written by the
// rules there), `offset` (constant added to the channel, e.g.
// 9.80665 on a vertical accelerometer), `quantum` (the output word's step: the filtered sum is
// rounded to it, kernels::ChannelSpec::quantum) and `lot_spread` ({term: relative sd}) are
// optional. A clock's channel may give its noise as power-law levels instead of (or beside)
// terms: `powerlaw` ({"h2", "h1", "h0", "hm1", "hm2"}: h_alpha of S_y(f) = h_alpha f^alpha in
// Hz^(-1-alpha), missing = 0; docs/clocks.md "Simulating clocks") and `output` ("frequency",
// the default, or "phase": the recording holds the time error x, data_type phase). Any other key, a
// wrong JSON type, a duplicate key, or an impossible value is an error whose message names the
// source and the key path, e.g.
//   "model.json: channels.gyro_x.terms.X: unknown key".
#pragma once

#include "kernels/simulate/simulate.hpp"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::model {

/// Every problem with a model file: "<source>: <key path>: <reason>".
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// One channel of a unit: its noise model (kernels/model/noise_model.hpp) in its own units, the
/// effects in file order within each type, plus what only the model file has. Its rate_hz and
/// flicker_pm are not read or written: to_spec sets them from the unit's sample rate and the
/// power-law levels.
struct Channel : kernels::NoiseModel {
  std::string name;             // [A-Za-z0-9_]+, the dataset name
  std::string units = "deg/s";  // units string (docs/formats.md, kernels/model/units.hpp)
  // Power-law levels h2, h1, h0, hm1, hm2 (kernels::powerlaw::kLevelKeys), added to the terms
  // by to_spec; all zero when the file has none.
  std::array<double, 5> powerlaw{};
  bool phase_output = false;  // "output": "phase": simulate writes the phase (time error)
  friend bool operator==(const Channel&, const Channel&) = default;
};

/// A unit: channels sharing one sample rate, plus the spread of the terms across a lot.
struct UnitModel {
  double sample_rate_hz = 1000;    // > 0
  std::vector<Channel> channels;   // non-empty, in file order, unique names
  kernels::NoiseTerms lot_spread;  // relative sd of each term across units (0 = none)
  bool single_channel = false;     // parsed from (and written back to) the single-channel form
  friend bool operator==(const UnitModel&, const UnitModel&) = default;
};

/// Parses and validates model JSON. `source` names the text in messages (the file name);
/// `single_channel_name` names the channel of a single-channel model (simulate --channel).
/// Throws model::Error.
UnitModel parse_model(std::string_view json_text, const std::string& source,
                      const std::string& single_channel_name = "gyro_x");

/// Reads and parses a model file; a file that cannot be read is a model::Error naming it.
UnitModel load_model(const std::string& path, const std::string& single_channel_name = "gyro_x");

/// The model as JSON (2-space indented) in the form it was read in; parse_model(to_json(m))
/// == m, doubles included (shortest round-trip representation). Effects are written by type in
/// kernels::kEffectLists order, then the filter.
std::string to_json(const UnitModel& m);

/// Throws model::Error if the model breaks a rule parse_model enforces (for models built in
/// code); `source` prefixes the message.
void validate(const UnitModel& m, const std::string& source);

/// A six-channel IMU at 1 kHz with the paper's Table (Lestev et al., JSC GIROOPTIKA unit):
/// gyro_x/y/z in deg/s and accel_x/y/z in m/s^2 (accel_z carries 1 g = 9.80665 m/s^2), the
/// Table's datasheet values converted with kernels/model/units.hpp, and a lot spread of 10% on N,
/// 20% on B, 30% on K and R (typical unit-to-unit variation of MEMS noise coefficients).
UnitModel default_demo_model();

/// Unit `unit_index` of a lot: each term T of each channel multiplied by a log-normal factor
/// exp(s g - s^2/2), s^2 = ln(1 + spread_T^2), g standard normal from Philox keyed by
/// (seed, unit_index, channel, term). Log-normal keeps coefficients positive (a truncated
/// normal would pile units at 0 or bias the mean), has mean exactly 1 (so the lot's mean
/// coefficient is the model's) and relative sd exactly spread_T. Deterministic; the returned
/// unit has no lot_spread. Throws std::invalid_argument for unit_index < 0.
UnitModel draw_unit(const UnitModel& lot, std::uint64_t seed, int unit_index);

/// The simulation spec of channel `channel` (< channels.size()).
kernels::ChannelSpec to_spec(const UnitModel& m, std::size_t channel);

/// The Philox stream for channel `channel` of unit `unit_index` (use with
/// kernels::simulate_channel): distinct for every (unit, channel) with channel < 2^20.
std::uint64_t channel_stream(int unit_index, std::size_t channel);

}  // namespace allanlot::model
