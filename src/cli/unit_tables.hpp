// The tables `analyze` prints for each unit (docs/cli.md "Command: analyze", "The terminal
// tables"): for IMU channels the paper-style table of the eq. (3) coefficients and read-outs
// (pipeline::fit_table); for clock data, whose noise is read from the deviations themselves
// rather than from angle and velocity random walks, a deviation table.
#pragma once

#include "io/results.hpp"

#include <string>

namespace allanlot::cli {

/// True for clock data: a channel in a clock's units (kernels::units::Family::Clock: s, time
/// error, or 1, fractional frequency, in any spelling of the vocabulary) or phase data in units
/// outside the IMU families. Gyro and accelerometer channels are IMU data whatever their data
/// type (an angle recording is the phase of a gyro).
bool is_clock_channel(const io::ChannelResult& ch);

/// The deviation table of one channel: one row per tau (at most one per octave when the curve
/// has more than 40 taus), one column per statistic computed, each "dev [lo, hi]" with the
/// bounds of its confidence interval where the statistic has one. The header names the channel,
/// its data type and the units: time errors (tdev, ttotdev, mtie, tierms) in phase units, the
/// others in rate units. "" for a channel without statistics.
std::string deviation_table(const std::string& device_id, const io::ChannelResult& ch);

/// Everything printed for one unit: pipeline::fit_table of its IMU channels, then the deviation
/// table of each clock channel that was analysed; `si`: the coefficients in SI units.
std::string unit_tables(const io::RecordingResult& rec, bool si = false);

}  // namespace allanlot::cli
