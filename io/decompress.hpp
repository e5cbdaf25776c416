// Whole-block decompression for the chunks of ROS bags and MCAP files, by the Debian
// libraries: bz2 (libbz2), lz4 frames (liblz4's LZ4F, which roslz4 and MCAP write) and zstd
// (libzstd).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::io {

/// "" when a chunk of `compressed` bytes may declare `declared` bytes uncompressed, else why
/// not: at most 1 GiB (writers make chunks of 1 to a few MiB) and at most 1000 times its
/// compressed size plus 1 MiB (IMU records never compress 1000:1), so that a corrupt size
/// is refused before it is allocated.
std::string declared_size_problem(std::uint64_t declared, std::size_t compressed);

/// Decompresses `in` into `out`, which holds the size the chunk declares; returns "" or why
/// it cannot (corrupt data, or a size other than declared).
std::string decompress(std::string_view codec, std::span<const unsigned char> in,
                       std::vector<unsigned char>& out);

}  // namespace allanlot::io
