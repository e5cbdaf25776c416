// ROS 1 bags (format 2.0; chunks uncompressed, bz2 or lz4) as a recording source: their
// sensor_msgs/Imu topics (io/imu_topics.hpp, docs/robotics.md).
#pragma once

#include "io/recording_source.hpp"

#include <cstdint>
#include <span>

namespace allanlot::io {

/// Recognises a file that starts `#ROSBAG V`.
SourceFormat ros1_bag_format();

class ImuTopics;

/// Reads the records of a bag held in `bytes` (`file` names it in errors) into `topics`.
void read_ros1_bag(std::span<const unsigned char> bytes, const std::string& file,
                   ImuTopics& topics);

}  // namespace allanlot::io
