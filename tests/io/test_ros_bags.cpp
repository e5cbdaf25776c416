// ROS 1 bags written by the official writer (Debian's python3-rosbag, tests/ros/) and ROS 2
// bags in rosbag2's sqlite3 schema through io::RecordingReader: every sensor_msgs/Imu topic as six
// channels in SI units, the samples bit for bit as written, dropped messages as gaps, --topic, and
// bad bags named.
#include "io/error.hpp"
#include "io/recording.hpp"
#include "support/ros_bags.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

template <class E = io::Error, class F>
std::string message_of(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

// A bag of two Imu topics at 200 Hz (/imu without rows 300..309) and a std_msgs/String topic.
struct Bag {
  fs::path path;
  test::ImuSamples imu, imu2;
};

Bag make_bag(const std::string& compression, const std::string& extra = "--string-topic /chatter") {
  Bag b;
  const fs::path dir = test::test_dir("ros_bags_" + compression);
  b.imu = test::imu_samples(1000, 200, 1);
  b.imu2 = test::imu_samples(600, 200, 2);
  std::set<std::size_t> dropped;
  for (std::size_t i = 300; i < 310; ++i)
    dropped.insert(i);
  test::write_imu_csv(dir / "imu.csv", b.imu, dropped);
  test::write_imu_csv(dir / "imu2.csv", b.imu2);
  b.path = dir / ("two_" + compression + ".bag");
  std::string log;
  const int rc = test::write_ros1_bag(b.path, compression,
                                      "/imu=" + (dir / "imu.csv").string() +
                                          " /imu2=" + (dir / "imu2.csv").string() + " " + extra,
                                      &log);
  EXPECT_EQ(rc, 0) << log;
  return b;
}

const io::ChannelInfo* find(const io::RecordingInfo& info, const std::string& path) {
  for (const auto& c : info.channels)
    if (c.path == path) return &c;
  return nullptr;
}

void expect_samples(const io::RecordingReader& r, const std::string& topic,
                    const test::ImuSamples& s, std::size_t gap_from, std::size_t gap_to) {
  const char* names[6] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (std::size_t k = 0; k < 6; ++k) {
    const io::ChannelInfo* c = find(r.info(), topic + "/" + names[k]);
    ASSERT_NE(c, nullptr) << topic << "/" << names[k];
    EXPECT_EQ(c->units, k < 3 ? "rad/s" : "m/s^2");
    EXPECT_NEAR(c->sample_rate_hz, 200.0, 1e-9);
    const auto v = test::as_vector(r.read(*c));
    ASSERT_EQ(v.size(), s.rows.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i >= gap_from && i < gap_to)
        EXPECT_TRUE(std::isnan(v[i])) << i;
      else
        ASSERT_EQ(v[i], s.rows[i][k]) << topic << " " << names[k] << " row " << i;
    }
  }
}

class RosBag : public ::testing::TestWithParam<std::string> {};

TEST_P(RosBag, EveryImuTopicBitForBitWithItsGap) {
  const Bag b = make_bag(GetParam());
  const io::RecordingReader r(b.path.string());
  ASSERT_EQ(r.info().channels.size(), 12u);
  EXPECT_EQ(r.info().channels.front().path, "/imu/accel_x");  // in path order, as HDF5's
  EXPECT_EQ(r.info().device_id, "two_" + GetParam());
  expect_samples(r, "/imu", b.imu, 300, 310);
  expect_samples(r, "/imu2", b.imu2, 0, 0);
  bool noted = false;
  for (const auto& n : r.info().notes)
    noted = noted || n.find("'/imu': 10 dropped message(s) in 1 place(s)") != std::string::npos;
  EXPECT_TRUE(noted);
}

INSTANTIATE_TEST_SUITE_P(Compressions, RosBag, ::testing::Values("none", "bz2", "lz4"));

TEST(RosBagTopics, SelectedByGlobAndNamedWhenNotImu) {
  const Bag b = make_bag("none");
  io::InputOptions o;
  o.topics = {"/imu2"};
  const io::RecordingReader r(b.path.string(), o);
  ASSERT_EQ(r.info().channels.size(), 6u);
  EXPECT_EQ(r.info().channels.front().path, "/imu2/accel_x");
  o.topics = {"/chat*"};
  const std::string e = message_of([&] { io::RecordingReader x(b.path.string(), o); });
  EXPECT_NE(e.find(b.path.string()), std::string::npos) << e;
  EXPECT_NE(e.find("/chatter"), std::string::npos) << e;
  EXPECT_NE(e.find("std_msgs/String topic, not sensor_msgs/Imu"), std::string::npos) << e;
  o.topics = {"/nothing"};
  const std::string none = message_of([&] { io::RecordingReader x(b.path.string(), o); });
  EXPECT_NE(none.find("--topic '/nothing' matches no topic"), std::string::npos) << none;
}

TEST(RosBagTopics, ReceiveTimesOnRequest) {
  const Bag b = make_bag("none");
  io::InputOptions o;
  o.receive_time = true;
  const io::RecordingReader r(b.path.string(), o);
  bool receive = false;
  for (const auto& [k, v] : r.info().facts)
    receive = receive || (k == "time_column" && v == "receive time");
  EXPECT_TRUE(receive);
  expect_samples(r, "/imu", b.imu, 300, 310);  // recorded 1 ms after each stamp
}

TEST(RosBagTopics, RepeatedAndOutOfOrderStampsCounted) {
  const fs::path dir = test::fresh_dir("ros_bags_order");
  test::ImuSamples s = test::imu_samples(400, 100, 3);
  std::swap(s.stamps_ns[100], s.stamps_ns[101]);  // one stamp out of order
  s.stamps_ns[200] = s.stamps_ns[199];            // one repeated
  test::write_imu_csv(dir / "imu.csv", s);
  std::string log;
  ASSERT_EQ(test::write_ros1_bag(dir / "o.bag", "none", "/imu=" + (dir / "imu.csv").string(), &log),
            0)
      << log;
  const io::RecordingReader r((dir / "o.bag").string());
  ASSERT_EQ(r.info().channels.size(), 6u);
  const auto& ts = r.info().channels[0].time_stamps;
  EXPECT_EQ(ts.n_decreasing, 1);
  EXPECT_EQ(ts.n_duplicate, 1);
  // As in a CSV: the stamp ahead of its turn spans two steps, one gap sample before it.
  EXPECT_EQ(r.info().channels[0].n_samples, 401);
}

TEST(RosBagErrors, NoImuTopicTruncatedAndUnknownCompression) {
  const fs::path dir = test::fresh_dir("ros_bags_bad");
  std::string log;
  ASSERT_EQ(test::write_ros1_bag(dir / "s.bag", "bz2", "--string-topic /chatter", &log), 0) << log;
  const std::string none = message_of([&] { io::RecordingReader r((dir / "s.bag").string()); });
  EXPECT_NE(none.find("no sensor_msgs/Imu topic (topics: /chatter (std_msgs/String))"),
            std::string::npos)
      << none;

  const Bag b = make_bag("bz2");
  const std::string bytes = test::file_bytes(b.path);
  std::ofstream(dir / "cut.bag", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const std::string cut = message_of([&] { io::RecordingReader r((dir / "cut.bag").string()); });
  EXPECT_NE(cut.find("cut.bag"), std::string::npos) << cut;
  EXPECT_NE(cut.find("truncated record"), std::string::npos) << cut;

  std::string xz = bytes;
  for (std::size_t p = 0; (p = xz.find("compression=bz2", p)) != std::string::npos;)
    xz.replace(p, 15, "compression=xz2");
  std::ofstream(dir / "xz.bag", std::ios::binary) << xz;
  const std::string unknown = message_of([&] { io::RecordingReader r((dir / "xz.bag").string()); });
  EXPECT_NE(unknown.find("xz.bag"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("chunk compression 'xz2' is none of none, bz2, lz4"), std::string::npos)
      << unknown;
}

// ROS 2: a bag folder (metadata.yaml and its .db3) and a .db3 alone, the same samples.
TEST(Ros2Bag, FolderAndFileBitForBitWithTheirGap) {
  const fs::path dir = test::fresh_dir("ros2_bags");
  const Bag b = make_bag("none");
  const fs::path csvs = b.path.parent_path();
  const std::string topics = "/imu=" + (csvs / "imu.csv").string() +
                             " /imu2=" + (csvs / "imu2.csv").string() + " --string-topic /chatter";
  std::string log;
  ASSERT_EQ(test::write_ros2_db3(dir / "rec", topics, &log), 0) << log;
  ASSERT_EQ(test::write_ros2_db3(dir / "one.db3", topics, &log), 0) << log;
  for (const fs::path& p : {dir / "rec", dir / "one.db3"}) {
    const io::RecordingReader r(p.string());
    ASSERT_EQ(r.info().channels.size(), 12u) << p;
    expect_samples(r, "/imu", b.imu, 300, 310);
    expect_samples(r, "/imu2", b.imu2, 0, 0);
  }
  EXPECT_EQ(io::RecordingReader((dir / "rec").string()).info().device_id, "rec");
  ASSERT_EQ(test::write_ros2_db3(dir / "s.db3", "--string-topic /chatter", &log), 0) << log;
  const std::string none = message_of([&] { io::RecordingReader r((dir / "s.db3").string()); });
  EXPECT_NE(none.find("no sensor_msgs/Imu topic (topics: /chatter (std_msgs/msg/String))"),
            std::string::npos)
      << none;
}

}  // namespace
}  // namespace allanlot
