// What the command line says about input recordings that the files themselves may not
// (docs/cli.md "Input options"): shared by every command that reads recordings.
#pragma once

#include "kernels/allan/phase.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace allanlot::io {

/// One --units rule: the unit of the columns whose channel `glob` matches ("" = every column).
struct ColumnUnits {
  std::string glob;
  std::string unit;
};

struct InputOptions {
  /// --data-type: the data type of every channel, overriding the files' `data_type`.
  std::optional<kernels::DataType> data_type;
  /// --sample-rate HZ or 1 / --tau0 S; 0 when not given. Text recordings without a time
  /// column need it; a text recording with one takes it instead of the time steps.
  double sample_rate_hz = 0.0;
  /// --column N: the 1-based column of a headerless text recording that holds the values.
  int column = 0;
  std::string time_column;  // --time-column NAME: the time column of a CSV/TSV
  std::string time_unit;    // --time-unit s|ms|us|ns: the unit of a numeric time column
  /// --units [GLOB=]UNIT, in the order given: the units of text columns (docs/formats.md
  /// "Text recordings"). A column takes the first rule whose glob matches its channel (name or
  /// path, as --channels), over its header's unit; else its header's unit; else the first rule
  /// without a glob.
  std::vector<ColumnUnits> units;
  /// --nominal-frequency HZ: the oscillator's nominal frequency F, with which a channel in Hz
  /// is read as fractional frequency (f - F) / F; 0 when not given (a channel in Hz is then a
  /// usage error).
  double nominal_frequency_hz = 0.0;
  /// Bytes a text recording's parsed samples (and its longest line) may hold, so that a gzip
  /// bomb or an endless line ends with an error naming the file and the limit instead of
  /// exhausting memory; 0 = no bound. The commands set --memory-limit, or their default (half
  /// of the machine's memory, src/workflow/memory.hpp).
  std::uint64_t memory_limit = 0;
  /// --topic GLOB, repeatable: the sensor_msgs/Imu topics of a ROS bag or MCAP file to read
  /// (docs/robotics.md); empty reads every Imu topic.
  std::vector<std::string> topics;
  /// --receive-time: a bag's messages timed by when they were recorded, not by their header
  /// stamps.
  bool receive_time = false;
};

/// The rules as one list, `gyro_*=deg/s,accel_*=g` (a bare unit alone as it is given).
inline std::string units_text(const std::vector<ColumnUnits>& rules) {
  std::string s;
  for (const ColumnUnits& r : rules)
    s += (s.empty() ? "" : ",") + (r.glob.empty() ? r.unit : r.glob + "=" + r.unit);
  return s;
}

}  // namespace allanlot::io
