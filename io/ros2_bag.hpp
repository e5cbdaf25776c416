// ROS 2 bags as a recording source: a bag folder (its metadata.yaml beside the storage files,
// sqlite3 `.db3` or `.mcap`, read in the order of their split numbers) or one `.db3` file of
// rosbag2's sqlite3 storage (tables `topics` and `messages`); their sensor_msgs/msg/Imu topics
// in CDR (io/imu_topics.hpp, docs/robotics.md).
#pragma once

#include "io/recording_source.hpp"

namespace allanlot::io {

/// Recognises a folder holding metadata.yaml, or a file that starts "SQLite format 3".
SourceFormat ros2_bag_format();

}  // namespace allanlot::io
