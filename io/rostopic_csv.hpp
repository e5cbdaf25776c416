// The CSV of `rostopic echo -p TOPIC` (ROS 1): its header line starts `%time,` (which would
// otherwise be a comment) and names the message's fields `field.header.stamp`,
// `field.angular_velocity.x`, ... (docs/robotics.md). A hook of the text reader's header
// parsing (io/text_recording.cpp).
#pragma once

#include "io/text_fields.hpp"

#include <string_view>
#include <vector>

namespace allanlot::io {

/// True for the header line of `rostopic echo -p`.
bool is_rostopic_header(std::string_view line);

/// Renames the header's cells as a sensor_msgs/Imu's channels (angular_velocity.x -> gyro_x
/// in rad/s, linear_acceleration.x -> accel_x in m/s^2; field.header.stamp -> the time
/// column stamp_ns) and returns, per column, whether it is not a channel (%time, the header's
/// other fields, the orientation and the covariances).
std::vector<bool> rostopic_cells(std::vector<HeaderCell>& cells);

}  // namespace allanlot::io
