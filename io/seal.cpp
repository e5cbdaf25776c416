#include "io/seal.hpp"

#include "io/error.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace allanlot::io {
namespace {

constexpr char kMagic[] = "allanlot-seal 1\n";

std::uint64_t fnv1a(const char* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a 64-bit offset basis and prime
  for (std::size_t i = 0; i < n; ++i)
    h = (h ^ static_cast<unsigned char>(p[i])) * 1099511628211ULL;
  return h;
}

bool has_magic(const std::vector<char>& bytes) {
  return bytes.size() >= sizeof kMagic - 1 &&
         std::memcmp(bytes.data(), kMagic, sizeof kMagic - 1) == 0;
}

std::string header(std::size_t size, std::uint64_t hash) {
  std::ostringstream s;
  s << kMagic << "bytes " << size << "\nhash " << std::hex << hash << "\n";
  return s.str();
}

}  // namespace

std::array<char, kSealBytes> seal_block(std::span<const char> body) {
  const std::string h = header(kSealBytes + body.size(), fnv1a(body.data(), body.size()));
  std::array<char, kSealBytes> block{};
  std::memcpy(block.data(), h.data(), h.size());
  return block;
}

SealCheck check_seal(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {SealState::Damaged, "cannot be read"};
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!has_magic(bytes)) {
    // Only sealed files have a user block, so an HDF5 signature at byte 512 means that the
    // seal itself was overwritten; an earlier version's file has its signature at byte 0.
    constexpr char kHdf5Signature[] = "\x89HDF\r\n\x1a\n";
    if (bytes.size() >= kSealBytes + 8 &&
        std::memcmp(bytes.data() + kSealBytes, kHdf5Signature, 8) == 0)
      return {SealState::Damaged, "its seal was overwritten"};
    return {SealState::Unsealed, ""};
  }
  if (bytes.size() < kSealBytes) return {SealState::Damaged, "shorter than its seal"};
  const std::string want =
      header(bytes.size(), fnv1a(bytes.data() + kSealBytes, bytes.size() - kSealBytes));
  const std::string have(bytes.data(), ::strnlen(bytes.data(), kSealBytes));
  if (have == want) return {SealState::Intact, ""};
  std::istringstream s(have.substr(sizeof kMagic - 1));
  std::string word;
  std::size_t size = 0;
  s >> word >> size;
  if (size != bytes.size())
    return {SealState::Damaged, "truncated or extended: " + std::to_string(bytes.size()) +
                                    " bytes, written as " + std::to_string(size)};
  return {SealState::Damaged, "its content changed after it was written (seal mismatch)"};
}

void reseal_file(const std::filesystem::path& path) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (!f.eof() && !f) throw Error(path.string(), "", "cannot read to seal it");
  if (bytes.size() < kSealBytes || !has_magic(bytes)) return;
  const auto block = seal_block({bytes.data() + kSealBytes, bytes.size() - kSealBytes});
  f.clear();
  f.seekp(0);
  f.write(block.data(), block.size());
  f.flush();
  if (!f) throw Error(path.string(), "", "cannot write its seal");
}

bool require_intact(const std::filesystem::path& path) {
  const SealCheck c = check_seal(path);
  if (c.state == SealState::Damaged) throw Error(path.string(), "", "damaged: " + c.reason);
  return c.state == SealState::Intact;
}

}  // namespace allanlot::io
