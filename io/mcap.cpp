// The records of MCAP (mcap.dev/spec): after the 8-byte magic, records of (opcode uint8,
// length uint64, content), little-endian, strings as uint32 length and bytes. The data section
// is read in order up to the footer; chunks (opcode 6) hold schema, channel and message
// records, compressed whole. Index and summary records are not needed to read every message.
#include "io/mcap.hpp"

#include "io/cdr_imu.hpp"
#include "io/decompress.hpp"
#include "io/error.hpp"
#include "io/imu_topics.hpp"
#include "io/mapped_file.hpp"
#include "io/utf8.hpp"

#include <map>
#include <string_view>

namespace allanlot::io {
namespace {

constexpr std::string_view kMagic("\x89MCAP0\r\n", 8);

enum Op : unsigned char {
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F
};

// A cursor over a record's content that refuses to read past it.
struct Cursor {
  std::span<const unsigned char> b;
  std::size_t p = 0;
  bool ok = true;
  template <class T>
  T get() {
    if (!ok || b.size() - p < sizeof(T)) {
      ok = false;
      return T{};
    }
    const T v = load_le<T>(b.data() + p);
    p += sizeof(T);
    return v;
  }
  std::span<const unsigned char> bytes(std::uint64_t n) {
    if (!ok || b.size() - p < n) {
      ok = false;
      return {};
    }
    const auto s = b.subspan(p, static_cast<std::size_t>(n));
    p += static_cast<std::size_t>(n);
    return s;
  }
  std::string str() {
    const auto s = bytes(get<std::uint32_t>());
    return {reinterpret_cast<const char*>(s.data()), s.size()};
  }
};

class McapReader {
public:
  McapReader(const std::string& file, ImuTopics& topics) : file_(file), topics_(topics) {}

  // Returns true at the footer (the end of the records).
  bool records(std::span<const unsigned char> buf, std::size_t base, bool in_chunk) {
    std::size_t p = 0;
    while (p < buf.size()) {
      const std::size_t at = base + p;
      if (buf.size() - p < 9) throw truncated(at, in_chunk);
      const unsigned char op = buf[p];
      const auto len = load_le<std::uint64_t>(buf.data() + p + 1);
      p += 9;
      if (buf.size() - p < len) throw truncated(at, in_chunk);
      Cursor c{buf.subspan(p, static_cast<std::size_t>(len))};
      p += static_cast<std::size_t>(len);
      if (op == kFooter && !in_chunk) return true;
      if (op == kSchema) schema(c, at, in_chunk);
      if (op == kChannel) channel(c, at, in_chunk);
      if (op == kMessage) message(c, at, in_chunk);
      if (op == kChunk && !in_chunk) chunk(c, at);
    }
    return false;
  }

private:
  std::string where(std::size_t at, bool in_chunk) const {
    return (in_chunk ? "chunk at byte " : "byte ") + std::to_string(at);
  }
  Error truncated(std::size_t at, bool in_chunk) const {
    return Error(file_, where(at, in_chunk),
                 "truncated record (the file ends inside it; was the recording cut short?)");
  }
  Error corrupt(std::size_t at, bool in_chunk, const char* what) const {
    return Error(file_, where(at, in_chunk),
                 std::string(what) + " record is cut short (corrupt MCAP)");
  }

  void schema(Cursor& c, std::size_t at, bool in_chunk) {
    const auto id = c.get<std::uint16_t>();
    std::string name = c.str();
    if (!c.ok) throw corrupt(at, in_chunk, "schema");
    schemas_[id] = std::move(name);
  }

  void channel(Cursor& c, std::size_t at, bool in_chunk) {
    const auto id = c.get<std::uint16_t>();
    const auto schema = c.get<std::uint16_t>();
    const std::string topic = valid_utf8(c.str());
    const std::string encoding = valid_utf8(c.str());
    if (!c.ok) throw corrupt(at, in_chunk, "channel");
    if (channels_.count(id)) return;  // repeated in the summary
    const auto s = schemas_.find(schema);
    const std::string type = s == schemas_.end() ? "(no schema)" : s->second;
    Channel ch{topic, encoding, -1};
    const bool imu =
        (type == kRos2ImuType && encoding == "cdr") || (type == kRos1ImuType && encoding == "ros1");
    if (!imu && (type == kRos2ImuType || type == kRos1ImuType))
      throw Error(file_, topic, "Imu messages in encoding '" + encoding + "' (read: cdr, ros1)");
    ch.index = topics_.add_topic(topic, type);
    channels_[id] = ch;
  }

  void message(Cursor& c, std::size_t at, bool in_chunk) {
    const auto id = c.get<std::uint16_t>();
    c.get<std::uint32_t>();  // sequence
    const auto log_time = c.get<std::uint64_t>();
    c.get<std::uint64_t>();  // publish time
    if (!c.ok) throw corrupt(at, in_chunk, "message");
    const auto it = channels_.find(id);
    if (it == channels_.end())
      throw Error(file_, where(at, in_chunk),
                  "message of channel " + std::to_string(id) + " before its definition");
    if (it->second.index < 0) return;
    ImuMessage m;
    m.receive_ns = static_cast<std::int64_t>(log_time);
    const auto data = c.b.subspan(c.p);
    const std::string why =
        it->second.encoding == "cdr" ? parse_cdr_imu(data, m) : parse_ros1_imu(data, m);
    if (!why.empty())
      throw Error(file_, it->second.topic, "message at " + where(at, in_chunk) + ": " + why);
    topics_.add(it->second.index, m);
  }

  void chunk(Cursor& c, std::size_t at) {
    c.get<std::uint64_t>();  // message start time
    c.get<std::uint64_t>();  // message end time
    const auto size = c.get<std::uint64_t>();
    c.get<std::uint32_t>();  // crc of the uncompressed records (0: not computed)
    const std::string compression = c.str();
    const auto records_len = c.get<std::uint64_t>();
    const auto data = c.bytes(records_len);
    if (!c.ok) throw corrupt(at, false, "chunk");
    if (compression.empty()) {
      records(data, at, true);
      return;
    }
    if (compression != "zstd" && compression != "lz4")
      throw Error(file_, where(at, false),
                  "chunk compression '" + valid_utf8(compression.substr(0, 40)) +
                      "' is none of zstd, lz4");
    if (const std::string why = declared_size_problem(size, data.size()); !why.empty())
      throw Error(file_, where(at, false), "chunk " + why + " (corrupt MCAP)");
    std::vector<unsigned char> out(static_cast<std::size_t>(size));
    if (const std::string why = decompress(compression, data, out); !why.empty())
      throw Error(file_, where(at, false), "chunk: " + why + " (corrupt MCAP)");
    records(out, at, true);
  }

  struct Channel {
    std::string topic, encoding;
    int index = -1;
  };
  const std::string& file_;
  ImuTopics& topics_;
  std::map<std::uint16_t, std::string> schemas_;
  std::map<std::uint16_t, Channel> channels_;
};

bool recognises_mcap(const std::string& path) {
  return starts_with_bytes(path, kMagic);
}

std::unique_ptr<RecordingSource> open_mcap(const std::string& path, const InputOptions& options) {
  const MappedFile map(path);
  ImuTopics topics(path, "MCAP", options);
  read_mcap(map.bytes(), path, topics);
  return topics.finish();
}

}  // namespace

void read_mcap(std::span<const unsigned char> bytes, const std::string& file, ImuTopics& topics) {
  if (bytes.size() < kMagic.size() ||
      std::string_view(reinterpret_cast<const char*>(bytes.data()), kMagic.size()) != kMagic)
    throw Error(file, "", "does not start with MCAP's magic bytes");
  if (!McapReader(file, topics).records(bytes.subspan(kMagic.size()), kMagic.size(), false))
    throw Error(file, "", "ends without MCAP's footer (truncated? was the recording cut short?)");
}

SourceFormat mcap_format() {
  return {"MCAP", recognises_mcap, nullptr, open_mcap};
}

}  // namespace allanlot::io
