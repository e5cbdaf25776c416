// A whole input file mapped read-only, for the readers of binary recordings that walk their
// records in one pass (ROS bags, MCAP): the kernel reads ahead, nothing is copied.
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace allanlot::io {

class MappedFile {
public:
  /// Throws io::Error naming the file when it cannot be opened or mapped, or is empty.
  explicit MappedFile(const std::string& file);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::span<const unsigned char> bytes() const {
    return {static_cast<const unsigned char*>(data_), size_};
  }

private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

/// True when the regular file `path` starts with `magic` (false for anything unreadable).
bool starts_with_bytes(const std::string& path, std::string_view magic);

}  // namespace allanlot::io
