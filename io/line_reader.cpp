#include "io/line_reader.hpp"

#include "io/error.hpp"

#include <zlib.h>

#include <cstdio>
#include <cstring>

namespace allanlot::io {

namespace {
constexpr std::size_t kBlock = std::size_t{1} << 20;
}  // namespace

struct LineReader::Gz {
  gzFile f = nullptr;
  ~Gz() {
    if (f) gzclose(f);
  }
};

LineReader::LineReader(const std::string& path, std::uint64_t max_line)
    : gz_(std::make_unique<Gz>()), path_(path), max_line_(max_line) {
  gz_->f = gzopen(path.c_str(), "rb");
  if (!gz_->f) throw Error(path, "", std::string("cannot open: ") + std::strerror(errno));
  // zlib's own buffer as large as ours: one read(2) per block for plain files too.
  gzbuffer(gz_->f, kBlock);
  buf_.resize(2 * kBlock);
}

LineReader::~LineReader() = default;

// Moves the unread tail to the front and appends the next block; false when nothing was added.
bool LineReader::refill() {
  if (eof_) return false;
  if (begin_ > 0) {
    std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  // A line longer than the buffer grows it: lines are never cut, but one longer than the
  // memory limit (a gzip bomb without line ends) is an error, not an allocation failure.
  if (max_line_ > 0 && end_ > max_line_)
    throw Error(path_, "line " + std::to_string(line_number_ + 1),
                "longer than the memory limit of " + memory_text(max_line_) +
                    " (--memory-limit) allows for its text: " + std::to_string(end_) +
                    " bytes without a line end");
  if (buf_.size() - end_ < kBlock) buf_.resize(buf_.size() + kBlock);
  const int got = gzread(gz_->f, buf_.data() + end_, static_cast<unsigned>(kBlock));
  if (got < 0) {
    int code = 0;
    const char* msg = gzerror(gz_->f, &code);
    throw Error(path_, "line " + std::to_string(line_number_ + 1),
                std::string("read error: ") + (msg ? msg : "unknown"));
  }
  if (got == 0) {
    // gzread returns 0 also for a gzip stream cut short; zlib says so through gzerror.
    int code = 0;
    const char* msg = gzerror(gz_->f, &code);
    if (code != Z_OK && code != Z_STREAM_END)
      throw Error(path_, "line " + std::to_string(line_number_ + 1),
                  std::string("truncated or corrupt compressed data: ") + (msg ? msg : ""));
    eof_ = true;
    return false;
  }
  end_ += static_cast<std::size_t>(got);
  return true;
}

bool LineReader::next(std::string_view& line) {
  std::size_t scanned = begin_;
  for (;;) {
    const void* nl = std::memchr(buf_.data() + scanned, '\n', end_ - scanned);
    if (nl) {
      const auto pos = static_cast<std::size_t>(static_cast<const char*>(nl) - buf_.data());
      std::size_t len = pos - begin_;
      if (len > 0 && buf_[begin_ + len - 1] == '\r') --len;
      line = std::string_view(buf_.data() + begin_, len);
      bytes_ += pos + 1 - begin_;
      begin_ = pos + 1;
      ++line_number_;
      return true;
    }
    const std::size_t offset = end_ - begin_;
    if (!refill()) break;
    scanned = begin_ + offset;
  }
  if (begin_ == end_) return false;
  // The last line without a line ending.
  std::size_t len = end_ - begin_;
  if (buf_[begin_ + len - 1] == '\r') --len;
  line = std::string_view(buf_.data() + begin_, len);
  bytes_ += end_ - begin_;
  begin_ = end_;
  ++line_number_;
  return true;
}

std::string memory_text(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

bool is_gzip_file(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  unsigned char magic[2] = {};
  const bool gz = std::fread(magic, 1, 2, f) == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
  std::fclose(f);
  return gz;
}

std::uint64_t text_size_hint(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return 0;
  unsigned char head[2] = {}, tail[4] = {};
  const bool gz = std::fread(head, 1, 2, f) == 2 && head[0] == 0x1f && head[1] == 0x8b;
  std::uint64_t size = 0;
  if (std::fseek(f, 0, SEEK_END) == 0) size = static_cast<std::uint64_t>(std::ftell(f));
  std::uint64_t text = size;
  if (gz && size >= 18 && std::fseek(f, -4, SEEK_END) == 0 && std::fread(tail, 1, 4, f) == 4) {
    // ISIZE, little-endian: the last member's uncompressed length modulo 2^32.
    const std::uint64_t isize =
        tail[0] | (tail[1] << 8) | (tail[2] << 16) | (static_cast<std::uint64_t>(tail[3]) << 24);
    text = isize >= size ? isize : 4 * size;
  }
  std::fclose(f);
  return text;
}

}  // namespace allanlot::io
