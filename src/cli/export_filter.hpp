// `allanlot export --format kalibr|openvins|vins`: the four IMU noise numbers a visual-inertial
// filter or calibrator asks for (docs/robotics.md), from the equation (3) fit of one IMU's
// results: white noise N as the noise density, rate random walk K as the bias random walk, in
// continuous-time SI units (rad/s/sqrt(Hz), rad/s^2/sqrt(Hz), m/s^2/sqrt(Hz),
// m/s^3/sqrt(Hz)).
#pragma once

#include "src/workflow/inputs.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

enum class FilterFormat { Kalibr, OpenVins, Vins };
enum class AxisCombine { Max, Mean };

struct FilterExport {
  FilterFormat format = FilterFormat::Kalibr;
  AxisCombine combine = AxisCombine::Max;
  std::filesystem::path output;  // "" = standard output
  workflow::ChannelSelection channels;
};

/// Writes the YAML of the one IMU the selected channels of `files` hold (its three gyro and
/// three accelerometer axes: the channels of one group, e.g. `/imu/gyro_x` ... `/imu/accel_z`).
/// Returns 0; 1 when some inputs could not be read; 2 when no IMU or more than one is
/// selected, a channel lacks its fit, or the output cannot be written.
int run_filter_export(const FilterExport& opt, const std::vector<std::filesystem::path>& files,
                      std::ostream& out, std::ostream& err);

}  // namespace allanlot::cli
