// Streaming reader of the lines of a text file, plain or gzip-compressed (zlib reads both
// through one interface), in large blocks: the text recordings of io/text_recording.hpp are
// parsed line by line without holding the file in memory.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::io {

class LineReader {
public:
  /// Opens `path` read-only. Throws io::Error naming the file when it cannot be opened.
  /// `max_line`: the longest line in bytes (0 = any); a longer one (an endless line of a
  /// gzip bomb) is an io::Error naming the line and the bound (the memory limit).
  explicit LineReader(const std::string& path, std::uint64_t max_line = 0);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// The next line without its line ending ("\n" or "\r\n"); false at the end of the file.
  /// The view is valid until the next call. Throws io::Error on a read error (a truncated
  /// gzip stream, an I/O error), naming the line reached.
  bool next(std::string_view& line);

  /// 1-based number of the line last returned.
  std::int64_t line_number() const { return line_number_; }
  /// Bytes of text consumed so far (after decompression).
  std::uint64_t bytes() const { return bytes_; }

private:
  bool refill();

  struct Gz;
  std::unique_ptr<Gz> gz_;
  std::string path_;
  std::vector<char> buf_;
  std::size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
  std::int64_t line_number_ = 0;
  std::uint64_t bytes_ = 0;
  std::uint64_t max_line_ = 0;
};

/// A memory size as messages give it: "512.0 MiB".
std::string memory_text(std::uint64_t bytes);

/// True when the file starts with the gzip magic bytes.
bool is_gzip_file(const std::string& path);

/// Bytes of text `path` holds: its size, or for gzip the size its trailer records (modulo
/// 2^32, so 4 times the compressed size where that is below the compressed size). A hint for
/// reserving memory, not a limit.
std::uint64_t text_size_hint(const std::string& path);

}  // namespace allanlot::io
