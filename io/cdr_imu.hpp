// sensor_msgs/msg/Imu in ROS 2's CDR (OMG CDR as ROS 2's rmw serializes it: little-endian
// XCDR1, the encapsulation header 00 01 00 00, each field aligned to its size counted from
// after the header), for ROS 2 bags and MCAP files (docs/robotics.md).
#pragma once

#include "io/imu_topics.hpp"

#include <span>
#include <string>

namespace allanlot::io {

/// Reads the header stamp, angular velocity and linear acceleration of one message into `m`;
/// returns "" or why it cannot be read.
std::string parse_cdr_imu(std::span<const unsigned char> data, ImuMessage& m);

/// The same message in ROS 1's serialization (ROS 1 bags, MCAP's `ros1` encoding).
std::string parse_ros1_imu(std::span<const unsigned char> data, ImuMessage& m);

}  // namespace allanlot::io
