// MCAP files (mcap.dev specification, version 0) as a recording source: the sensor_msgs/msg/Imu
// channels of ROS 2 (CDR) or ROS 1 encoding, in chunks compressed with zstd or lz4 or not,
// with or without a summary and indexes (io/imu_topics.hpp, docs/robotics.md).
#pragma once

#include "io/recording_source.hpp"

#include <span>

namespace allanlot::io {

class ImuTopics;

/// Recognises a file that starts with MCAP's magic, 0x89 "MCAP0\r\n".
SourceFormat mcap_format();

/// Reads the records of an MCAP file held in `bytes` (`file` names it in errors) into `topics`.
void read_mcap(std::span<const unsigned char> bytes, const std::string& file, ImuTopics& topics);

}  // namespace allanlot::io
