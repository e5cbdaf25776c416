// Whole-block decompression for the chunks of ROS bags and MCAP files, by the Debian
// libraries: bz2 (libbz2), lz4 frames (liblz4's LZ4F, which roslz4 and MCAP write) and zstd
// (libzstd).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::io {

/// True for "bz2", "lz4" and "zstd".
bool known_compression(std::string_view codec);

/// Decompresses `in` into `out`, which holds the size the chunk declares; returns "" or why
/// it cannot (corrupt data, or a size other than declared).
std::string decompress(std::string_view codec, std::span<const unsigned char> in,
                       std::vector<unsigned char>& out);

}  // namespace allanlot::io
