// MCAP files written by the official writer (@mcap/core, tests/data/mcap/ and its README entry)
// through io::RecordingReader: zstd, lz4 and uncompressed chunks, and a file without chunks or
// index; every sensor_msgs/msg/Imu topic as six channels, bit for bit the CSV it was written
// from, dropped messages as gaps; truncated files and unknown compression named.
#include "io/error.hpp"
#include "io/recording.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(ALLANLOT_REFERENCE_DIR) / "mcap";

template <class F>
std::string message_of(F f) {
  try {
    f();
  } catch (const io::Error& e) {
    return e.what();
  }
  return "";
}

// The CSV the samples were written from: stamp (ns) and six values per row.
std::vector<std::pair<long long, std::array<double, 6>>> rows(const fs::path& csv) {
  std::vector<std::pair<long long, std::array<double, 6>>> out;
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f;
    std::getline(ss, f, ',');
    std::pair<long long, std::array<double, 6>> r{std::stoll(f), {}};
    for (double& v : r.second) {
      std::getline(ss, f, ',');
      v = std::strtod(f.c_str(), nullptr);
    }
    out.push_back(r);
  }
  return out;
}

// Each channel of `topic` holds the CSV's values at their stamps' sample numbers, NaN between.
void expect_topic(const io::RecordingReader& r, const std::string& topic, const fs::path& csv,
                  double rate_hz) {
  const auto want = rows(csv);
  const char* names[6] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (std::size_t k = 0; k < 6; ++k) {
    const io::ChannelInfo* c = nullptr;
    for (const auto& ch : r.info().channels)
      if (ch.path == topic + "/" + names[k]) c = &ch;
    ASSERT_NE(c, nullptr) << topic << "/" << names[k];
    EXPECT_EQ(c->units, k < 3 ? "rad/s" : "m/s^2");
    EXPECT_NEAR(c->sample_rate_hz, rate_hz, 1e-9);
    const auto v = test::as_vector(r.read(*c));
    const auto step = static_cast<long long>(1e9 / rate_hz);
    ASSERT_EQ(static_cast<long long>(v.size()), (want.back().first - want[0].first) / step + 1);
    std::size_t nan = 0;
    for (const auto& [ns, values] : want)
      ASSERT_EQ(v[static_cast<std::size_t>((ns - want[0].first) / step)], values[k]);
    for (double x : v)
      nan += std::isnan(x) ? 1 : 0;
    EXPECT_EQ(nan, v.size() - want.size());
  }
}

class Mcap : public ::testing::TestWithParam<std::string> {};

TEST_P(Mcap, EveryImuTopicBitForBitWithItsGap) {
  const io::RecordingReader r((kDir / ("imu_" + GetParam() + ".mcap")).string());
  ASSERT_EQ(r.info().channels.size(), 12u);
  expect_topic(r, "/imu", kDir / "imu.csv", 200);
  expect_topic(r, "/imu2", kDir / "imu2.csv", 100);
  bool noted = false;
  for (const auto& n : r.info().notes)
    noted = noted || n.find("'/imu': 10 dropped message(s)") != std::string::npos;
  EXPECT_TRUE(noted);
}

INSTANTIATE_TEST_SUITE_P(Layouts, Mcap, ::testing::Values("zstd", "lz4", "chunked", "plain"));

TEST(McapTopics, SelectedAndNamed) {
  io::InputOptions o;
  o.topics = {"/imu2"};
  const io::RecordingReader r((kDir / "imu_zstd.mcap").string(), o);
  EXPECT_EQ(r.info().channels.size(), 6u);
  o.topics = {"/chatter"};
  const std::string e =
      message_of([&] { io::RecordingReader x((kDir / "imu_zstd.mcap").string(), o); });
  EXPECT_NE(e.find("/chatter: is a std_msgs/msg/String topic, not sensor_msgs/Imu"),
            std::string::npos)
      << e;
}

TEST(McapErrors, TruncatedAndUnknownCompressionNamed) {
  const fs::path dir = test::fresh_dir("mcap_bad");
  const std::string bytes = test::file_bytes(kDir / "imu_zstd.mcap");
  std::ofstream(dir / "cut.mcap", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const std::string cut = message_of([&] { io::RecordingReader r((dir / "cut.mcap").string()); });
  EXPECT_NE(cut.find("cut.mcap"), std::string::npos) << cut;
  EXPECT_NE(cut.find("truncated record"), std::string::npos) << cut;

  std::string other = bytes;
  const std::string zstd("\x04\x00\x00\x00zstd", 8);
  for (std::size_t p = 0; (p = other.find(zstd, p)) != std::string::npos;)
    other.replace(p, 8, std::string("\x04\x00\x00\x00zxxd", 8));
  std::ofstream(dir / "other.mcap", std::ios::binary) << other;
  const std::string unknown =
      message_of([&] { io::RecordingReader r((dir / "other.mcap").string()); });
  EXPECT_NE(unknown.find("chunk compression 'zxxd' is none of zstd, lz4"), std::string::npos)
      << unknown;

  // The first chunk (after the magic and the header record) declaring 2^39 bytes: refused
  // before anything is allocated.
  std::string huge = bytes;
  std::uint64_t header_len = 0;
  std::memcpy(&header_len, huge.data() + 9, 8);
  const std::size_t chunk = 8 + 9 + static_cast<std::size_t>(header_len);
  ASSERT_EQ(huge[chunk], '\x06');
  const std::uint64_t declared = std::uint64_t{1} << 39;
  std::memcpy(huge.data() + chunk + 9 + 16, &declared, 8);
  std::ofstream(dir / "huge.mcap", std::ios::binary) << huge;
  const std::string big = message_of([&] { io::RecordingReader r((dir / "huge.mcap").string()); });
  EXPECT_NE(big.find("chunk declares 549755813888 bytes uncompressed"), std::string::npos) << big;
}

}  // namespace
}  // namespace allanlot
