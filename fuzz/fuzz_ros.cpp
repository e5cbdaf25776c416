// libFuzzer target: the hand-parsed records of ROS 1 bags (io/ros1_bag.cpp) and MCAP files
// (io/mcap.cpp) and the Imu messages in them (io/cdr_imu.cpp: CDR and ROS 1 serialization).
// The first byte chooses the parser; the rest is the file after its magic bytes (which the
// target supplies), or one message. Reading must throw nothing but io::Error; what it returns
// must be whole: six channels a topic, all of one length, paths that start with '/'.
#include "io/cdr_imu.hpp"
#include "io/error.hpp"
#include "io/imu_topics.hpp"
#include "io/mcap.hpp"
#include "io/ros1_bag.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  if (size == 0) return 0;
  const std::span<const unsigned char> rest(data + 1, size - 1);
  if (data[0] % 3 == 2) {  // one message: any bytes are read or refused, never overrun
    io::ImuMessage m;
    (void)io::parse_cdr_imu(rest, m);
    (void)io::parse_ros1_imu(rest, m);
    return 0;
  }
  const std::string_view magic =
      data[0] % 3 == 0 ? std::string_view("#ROSBAG V2.0\n") : std::string_view("\x89MCAP0\r\n", 8);
  std::vector<unsigned char> file(magic.begin(), magic.end());
  file.insert(file.end(), rest.begin(), rest.end());
  io::InputOptions opt;
  opt.receive_time = (data[0] & 8) != 0;
  try {
    io::ImuTopics topics("fuzz", "fuzz", opt);
    if (data[0] % 3 == 0)
      io::read_ros1_bag(file, "fuzz", topics);
    else
      io::read_mcap(file, "fuzz", topics);
    const auto source = topics.finish();
    const io::RecordingInfo info = source->describe();
    if (info.channels.size() % 6 != 0) std::abort();
    for (const io::ChannelInfo& ch : info.channels) {
      if (ch.path.empty() || ch.path[0] != '/') std::abort();
      if (source->read(ch, 1 << 20).size() != static_cast<std::size_t>(ch.n_samples)) std::abort();
    }
  } catch (const io::Error&) {
    // Named problems (truncated records, corrupt chunks, no Imu topic) are the expected outcome.
  }
  return 0;
}
