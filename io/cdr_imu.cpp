#include "io/cdr_imu.hpp"

#include <cstdint>

namespace allanlot::io {
namespace {

// The 37 float64 after the header: orientation[4], its covariance[9], angular_velocity[3],
// covariance[9], linear_acceleration[3], covariance[9].
constexpr std::size_t kDoubles = 37;
constexpr std::size_t kGyro = 13, kAccel = 25;

void take_vectors(const unsigned char* v, ImuMessage& m) {
  for (std::size_t k = 0; k < 3; ++k) {
    m.gyro[k] = load_le<double>(v + 8 * (kGyro + k));
    m.accel[k] = load_le<double>(v + 8 * (kAccel + k));
  }
}

}  // namespace

std::string parse_cdr_imu(std::span<const unsigned char> d, ImuMessage& m) {
  if (d.size() < 4 + 12) return "shorter than a CDR Imu header";
  if (d[0] != 0x00 || d[1] != 0x01)
    return "CDR encapsulation " + std::to_string(d[0]) + " " + std::to_string(d[1]) +
           " is not little-endian plain CDR (00 01)";
  const unsigned char* b = d.data() + 4;  // alignment counts from here
  const std::size_t n = d.size() - 4;
  const auto sec = load_le<std::int32_t>(b);
  const auto nsec = load_le<std::uint32_t>(b + 4);
  const auto len = load_le<std::uint32_t>(b + 8);  // frame_id's bytes with its NUL
  if (len > n - 12) return "frame_id longer than the message";
  std::size_t p = 12 + len;
  p = (p + 7) & ~std::size_t{7};
  if (p > n || n - p < kDoubles * 8) return "shorter than a sensor_msgs/msg/Imu";
  m.header_ns = static_cast<std::int64_t>(sec) * 1000000000 + nsec;
  take_vectors(b + p, m);
  return "";
}

std::string parse_ros1_imu(std::span<const unsigned char> d, ImuMessage& m) {
  // Header: uint32 seq, uint32 sec, uint32 nsec, string frame_id (uint32 length, bytes).
  if (d.size() < 16) return "shorter than an Imu header";
  const auto sec = load_le<std::uint32_t>(d.data() + 4);
  const auto nsec = load_le<std::uint32_t>(d.data() + 8);
  const auto len = load_le<std::uint32_t>(d.data() + 12);
  if (d.size() - 16 < std::size_t{len} + kDoubles * 8) return "shorter than a sensor_msgs/Imu";
  m.header_ns = static_cast<std::int64_t>(sec) * 1000000000 + nsec;
  take_vectors(d.data() + 16 + len, m);
  return "";
}

}  // namespace allanlot::io
