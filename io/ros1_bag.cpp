// The record layout is that of the ROS wiki's "Bags/Format/2.0": after the line
// `#ROSBAG V2.0\n`, records of (header length, header fields `name=value` each with its length,
// data length, data), all lengths little-endian uint32. Chunks hold connection and message
// records, compressed whole; index records are not needed to read every message in order.
#include "io/ros1_bag.hpp"

#include "io/cdr_imu.hpp"
#include "io/error.hpp"
#include "io/imu_topics.hpp"
#include "io/utf8.hpp"

#include "io/decompress.hpp"
#include "io/mapped_file.hpp"

#include <cstring>
#include <map>
#include <string_view>

namespace allanlot::io {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";

enum Op : unsigned char {
  kMessage = 2,
  kBagHeader = 3,
  kIndex = 4,
  kChunk = 5,
  kChunkInfo = 6,
  kConnection = 7
};

// One record: its header fields and its data.
struct Record {
  std::span<const unsigned char> header, data;
  std::size_t at = 0;  // byte offset of the record in its buffer
};

// The value of header field `name`, empty when absent.
std::span<const unsigned char> field(std::span<const unsigned char> header, std::string_view name) {
  std::size_t p = 0;
  while (p + 4 <= header.size()) {
    const auto len = load_le<std::uint32_t>(header.data() + p);
    p += 4;
    if (len > header.size() - p) break;
    const std::string_view f(reinterpret_cast<const char*>(header.data() + p), len);
    p += len;
    const auto eq = f.find('=');
    if (eq != std::string_view::npos && f.substr(0, eq) == name)
      return header.subspan(p - len + eq + 1, len - eq - 1);
  }
  return {};
}

std::string text_field(std::span<const unsigned char> header, std::string_view name) {
  const auto v = field(header, name);
  return {reinterpret_cast<const char*>(v.data()), v.size()};
}

template <class T>
bool int_field(std::span<const unsigned char> header, std::string_view name, T& out) {
  const auto v = field(header, name);
  if (v.size() != sizeof(T)) return false;
  out = load_le<T>(v.data());
  return true;
}

class BagReader {
public:
  BagReader(const std::string& file, ImuTopics& topics) : file_(file), topics_(topics) {}

  // The records of `buf` (the file after its magic line, or a chunk's uncompressed bytes);
  // `base` is where buf starts in the file, for the offsets errors name.
  void records(std::span<const unsigned char> buf, std::size_t base, bool in_chunk) {
    std::size_t p = 0;
    while (p < buf.size()) {
      const Record r = next(buf, p, base, in_chunk);
      unsigned char op = 0;
      if (!int_field(r.header, "op", op))
        throw Error(file_, where(base + r.at, in_chunk),
                    "record without an op field (corrupt bag)");
      if (op == kChunk && !in_chunk) chunk(r, base);
      if (op == kConnection) connection(r, base, in_chunk);
      if (op == kMessage) message(r, base, in_chunk);
    }
  }

private:
  std::string where(std::size_t offset, bool in_chunk) const {
    return (in_chunk ? "chunk at byte " : "byte ") + std::to_string(offset);
  }

  Record next(std::span<const unsigned char> buf, std::size_t& p, std::size_t base, bool in_chunk) {
    Record r;
    r.at = p;
    const auto truncated = [&] {
      return Error(file_, where(base + r.at, in_chunk),
                   "truncated record (the bag ends inside it; was the recording cut short?)");
    };
    if (buf.size() - p < 4) throw truncated();
    const auto hlen = load_le<std::uint32_t>(buf.data() + p);
    p += 4;
    if (buf.size() - p < std::size_t{hlen} + 4) throw truncated();
    r.header = buf.subspan(p, hlen);
    p += hlen;
    const auto dlen = load_le<std::uint32_t>(buf.data() + p);
    p += 4;
    if (buf.size() - p < dlen) throw truncated();
    r.data = buf.subspan(p, dlen);
    p += dlen;
    return r;
  }

  void chunk(const Record& r, std::size_t base) {
    const std::string compression = text_field(r.header, "compression");
    std::uint32_t size = 0;
    if (!int_field(r.header, "size", size))
      throw Error(file_, where(base + r.at, false), "chunk without its size (corrupt bag)");
    const std::size_t at = base + r.at;
    if (compression == "none") {
      if (r.data.size() != size)
        throw Error(file_, where(at, false), "chunk size does not match its data (corrupt bag)");
      records(r.data, at, true);
      return;
    }
    if (compression != "bz2" && compression != "lz4")
      throw Error(file_, where(at, false),
                  "chunk compression '" + valid_utf8(compression.substr(0, 40)) +
                      "' is none of none, bz2, lz4");
    if (const std::string why = declared_size_problem(size, r.data.size()); !why.empty())
      throw Error(file_, where(at, false), "chunk " + why + " (corrupt bag)");
    buffer_.resize(size);
    if (const std::string why = decompress(compression, r.data, buffer_); !why.empty())
      throw Error(file_, where(at, false), "chunk: " + why + " (corrupt bag)");
    std::vector<unsigned char> mine;
    mine.swap(buffer_);
    records(mine, at, true);
    mine.swap(buffer_);
  }

  void connection(const Record& r, std::size_t base, bool in_chunk) {
    std::uint32_t conn = 0;
    if (!int_field(r.header, "conn", conn))
      throw Error(file_, where(base + r.at, in_chunk), "connection without its id (corrupt bag)");
    if (conns_.count(conn)) return;  // repeated in each chunk that uses it and at the end
    const std::string topic = valid_utf8(text_field(r.header, "topic"));
    conns_[conn] = {topic, topics_.add_topic(topic, text_field(r.data, "type"))};
  }

  void message(const Record& r, std::size_t base, bool in_chunk) {
    std::uint32_t conn = 0;
    std::uint64_t time = 0;
    if (!int_field(r.header, "conn", conn) || !int_field(r.header, "time", time))
      throw Error(file_, where(base + r.at, in_chunk),
                  "message without conn or time (corrupt bag)");
    const auto it = conns_.find(conn);
    if (it == conns_.end())
      throw Error(file_, where(base + r.at, in_chunk),
                  "message of connection " + std::to_string(conn) + " before its definition");
    if (it->second.index < 0) return;
    ImuMessage m;
    // time: uint32 seconds, then uint32 nanoseconds (ros::Time).
    m.receive_ns = static_cast<std::int64_t>(time & 0xffffffffu) * 1000000000 +
                   static_cast<std::int64_t>(time >> 32);
    if (const std::string why = parse_ros1_imu(r.data, m); !why.empty())
      throw Error(file_, it->second.topic,
                  "message at " + where(base + r.at, in_chunk) + ": " + why);
    topics_.add(it->second.index, m);
  }

  struct Conn {
    std::string topic;
    int index = -1;
  };
  const std::string& file_;
  ImuTopics& topics_;
  std::map<std::uint32_t, Conn> conns_;
  std::vector<unsigned char> buffer_;
};

bool recognises_bag(const std::string& path) {
  return starts_with_bytes(path, "#ROSBAG V");
}

std::unique_ptr<RecordingSource> open_bag(const std::string& path, const InputOptions& options) {
  const MappedFile map(path);
  const auto bytes = map.bytes();
  if (bytes.size() < kMagic.size() || std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    throw Error(path, "", "a ROS bag of a version other than 2.0 (the only one read)");
  ImuTopics topics(path, "ROS 1 bag", options);
  read_ros1_bag(bytes, path, topics);
  return topics.finish();
}

}  // namespace

void read_ros1_bag(std::span<const unsigned char> bytes, const std::string& file,
                   ImuTopics& topics) {
  if (bytes.size() < kMagic.size()) throw Error(file, "", "shorter than a bag's first line");
  BagReader(file, topics).records(bytes.subspan(kMagic.size()), kMagic.size(), false);
}

SourceFormat ros1_bag_format() {
  return {"ROS 1 bag", recognises_bag, nullptr, open_bag};
}

}  // namespace allanlot::io
