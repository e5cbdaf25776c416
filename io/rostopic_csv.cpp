#include "io/rostopic_csv.hpp"

#include <array>
#include <string>
#include <utility>

namespace allanlot::io {

bool is_rostopic_header(std::string_view line) {
  return line.starts_with("%time,") || line.starts_with("%time\t");
}

std::vector<bool> rostopic_cells(std::vector<HeaderCell>& cells) {
  // sensor_msgs/Imu's vectors, in the units REP 103 gives them.
  static const std::array<std::pair<std::string_view, std::string_view>, 2> kImu = {{
      {"field.angular_velocity.", "gyro_"},
      {"field.linear_acceleration.", "accel_"},
  }};
  std::vector<bool> not_channel(cells.size(), false);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    HeaderCell& cell = cells[c];
    const std::string_view name = cell.name;
    if (name == "field.header.stamp") {
      cell.name = "stamp_ns";  // a time column, in ns since the epoch
      continue;
    }
    bool imu = false;
    for (const auto& [prefix, channel] : kImu)
      if (name.starts_with(prefix) && name.size() == prefix.size() + 1) {
        cell.unit = channel == "gyro_" ? "rad/s" : "m/s^2";
        cell.name = std::string(channel) + std::string(name.substr(prefix.size()));
        imu = true;
      }
    if (imu) continue;
    not_channel[c] = name == "%time" || name.starts_with("field.header.") ||
                     name.starts_with("field.orientation") ||
                     name.find("_covariance") != std::string_view::npos;
    if (!not_channel[c] && name.starts_with("field.")) cell.name = name.substr(6);
  }
  return not_channel;
}

}  // namespace allanlot::io
