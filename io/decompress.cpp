#include "io/decompress.hpp"

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

namespace allanlot::io {
namespace {

std::string bz2(std::span<const unsigned char> in, std::vector<unsigned char>& out) {
  auto n = static_cast<unsigned>(out.size());
  const int rc =
      BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &n,
                                 const_cast<char*>(reinterpret_cast<const char*>(in.data())),
                                 static_cast<unsigned>(in.size()), 0, 0);
  if (rc != BZ_OK) return "corrupt bz2 data (libbz2 error " + std::to_string(rc) + ")";
  if (n != out.size()) return "bz2 data decompress to a size other than declared";
  return "";
}

std::string lz4(std::span<const unsigned char> in, std::vector<unsigned char>& out) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
    return "cannot start lz4 decompression";
  std::size_t done = 0, used = 0, rc = 1;
  while (rc != 0 && used < in.size()) {
    std::size_t out_n = out.size() - done, in_n = in.size() - used;
    rc = LZ4F_decompress(ctx, out.data() + done, &out_n, in.data() + used, &in_n, nullptr);
    if (LZ4F_isError(rc)) break;
    done += out_n;
    used += in_n;
    if (out_n == 0 && in_n == 0) break;
  }
  LZ4F_freeDecompressionContext(ctx);
  if (LZ4F_isError(rc)) return std::string("corrupt lz4 data (") + LZ4F_getErrorName(rc) + ")";
  if (done != out.size()) return "lz4 data decompress to a size other than declared";
  return "";
}

std::string zstd(std::span<const unsigned char> in, std::vector<unsigned char>& out) {
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
  if (ZSTD_isError(n)) return std::string("corrupt zstd data (") + ZSTD_getErrorName(n) + ")";
  if (n != out.size()) return "zstd data decompress to a size other than declared";
  return "";
}

}  // namespace

std::string declared_size_problem(std::uint64_t declared, std::size_t compressed) {
  constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 30;
  if (declared <= kMaxChunk && declared <= 1000 * std::uint64_t{compressed} + (1 << 20)) return "";
  return "declares " + std::to_string(declared) + " bytes uncompressed from " +
         std::to_string(compressed) + " (more than 1 GiB, or 1000 times its size)";
}

std::string decompress(std::string_view codec, std::span<const unsigned char> in,
                       std::vector<unsigned char>& out) {
  if (codec == "bz2") return bz2(in, out);
  if (codec == "lz4") return lz4(in, out);
  if (codec == "zstd") return zstd(in, out);
  return "unknown compression '" + std::string(codec.substr(0, 40)) + "'";
}

}  // namespace allanlot::io
