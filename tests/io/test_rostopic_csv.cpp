// The CSV of `rostopic echo -p /imu`: its `%time,...` header is the header (not a comment),
// field.header.stamp the time column in ns, the Imu's vectors six channels in rad/s and
// m/s^2, the orientation, covariances and other header fields no channel.
#include "io/recording.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace allanlot {
namespace {

TEST(RostopicCsv, ImuFieldsAreSixChannelsInSiUnits) {
  const auto dir = test::fresh_dir("rostopic_csv");
  const auto file = dir / "imu.csv";
  std::ofstream f(file);
  f << "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.orientation.x,"
       "field.orientation.y,field.orientation.z,field.orientation.w,"
       "field.orientation_covariance0,field.angular_velocity.x,field.angular_velocity.y,"
       "field.angular_velocity.z,field.angular_velocity_covariance0,"
       "field.linear_acceleration.x,field.linear_acceleration.y,field.linear_acceleration.z,"
       "field.linear_acceleration_covariance0\n";
  // 200 Hz; the fourth message 10 ms after the third: one dropped.
  const long long stamps[4] = {5000000, 10000000, 15000000, 25000000};
  for (int i = 0; i < 4; ++i)
    f << 1700000000001000000 + stamps[i] << "," << i + 1 << "," << 1700000000000000000 + stamps[i]
      << ",imu_link,0,0,0,1,0," << 0.01 * i << ",-0.02,0.03,0,0.1,0.2," << 9.81 + i << ",0\n";
  f.close();
  const io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 6u);
  const char* names[6] = {"/accel_x", "/accel_y", "/accel_z", "/gyro_x", "/gyro_y", "/gyro_z"};
  for (std::size_t k = 0; k < 6; ++k) {
    const io::ChannelInfo& c = r.info().channels[k];
    EXPECT_EQ(c.path, names[k]);
    EXPECT_EQ(c.units, k < 3 ? "m/s^2" : "rad/s");
    EXPECT_NEAR(c.sample_rate_hz, 200.0, 1e-6);
    EXPECT_EQ(c.n_samples, 5);
  }
  const auto z = test::as_vector(r.read(r.info().channels[2]));
  EXPECT_EQ(z[0], 9.81);
  EXPECT_EQ(z[2], 11.81);
  EXPECT_TRUE(std::isnan(z[3]));
  EXPECT_EQ(z[4], 12.81);
}

}  // namespace
}  // namespace allanlot
