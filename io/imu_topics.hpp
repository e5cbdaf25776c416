// The sensor_msgs/Imu topics of a ROS 1 bag, a ROS 2 bag or an MCAP file (docs/robotics.md):
// the readers of those formats hand each topic and each Imu message to an ImuTopics, which
// selects the topics (--topic), times the samples (header stamps, or receive times with
// --receive-time), finds dropped messages as gaps and out-of-order or repeated stamps as the
// text reader does (io/time_axis.hpp), and makes six channels a topic:
// `<topic>/gyro_x|y|z` in rad/s and `<topic>/accel_x|y|z` in m/s^2.
#pragma once

#include "io/recording_source.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace allanlot::io {

/// The ROS type names of an Imu message.
inline constexpr const char* kRos1ImuType = "sensor_msgs/Imu";
inline constexpr const char* kRos2ImuType = "sensor_msgs/msg/Imu";

/// What one Imu message says: its header stamp, when it was recorded (ns since the epoch) and
/// its angular velocity (rad/s) and linear acceleration (m/s^2).
struct ImuMessage {
  std::int64_t header_ns = 0;
  std::int64_t receive_ns = 0;
  std::array<double, 3> gyro{};
  std::array<double, 3> accel{};
};

class ImuTopics {
public:
  /// `layout` names the format in the recording's facts ("ROS 1 bag", ...).
  ImuTopics(std::string file, std::string layout, const InputOptions& options);

  /// A topic of the file and its message type, once each; returns the topic's index for add(),
  /// or -1 when its messages are not read (not Imu, or not selected by --topic).
  int add_topic(const std::string& topic, const std::string& type);
  void add(int topic, const ImuMessage& message) {
    topics_[static_cast<std::size_t>(topic)].push_back(message);
  }

  /// The recording: throws io::Error naming the file (and topic) when no Imu topic is read or
  /// a --topic selects none.
  std::unique_ptr<RecordingSource> finish();

private:
  std::string file_, layout_;
  const InputOptions& options_;
  std::vector<std::pair<std::string, std::string>> all_;  // every topic and its type
  std::vector<std::string> names_;                        // the topics read
  std::vector<std::vector<ImuMessage>> topics_;           // their messages, as recorded
};

/// The little-endian integers and floats of ROS 1 records and CDR.
template <class T>
T load_le(const unsigned char* p) {
  T v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace allanlot::io
