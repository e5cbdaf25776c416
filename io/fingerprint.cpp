#include "io/fingerprint.hpp"

#include "io/seal.hpp"

#include "io/hdf5_handle.hpp"

#include <hdf5.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

namespace allanlot::io {
namespace {

// One SplitMix64-style finalizer step per 64-bit word: constants of Steele, Lea & Flood,
// "Fast splittable pseudorandom number generators", OOPSLA 2014.
std::uint64_t mix(std::uint64_t h, std::uint64_t w) {
  h ^= w + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

}  // namespace

std::optional<ResultsStamp> read_results_stamp(const std::filesystem::path& results) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(results, ec)) return std::nullopt;
  // Only a file that is byte for byte what allanlot wrote is trusted: a damaged or edited one,
  // or one of an earlier version without a seal, is redone (io/seal.hpp).
  if (check_seal(results).state != SealState::Intact) return std::nullopt;
  h5::quiet_library();
  const std::string file = results.string();
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return std::nullopt;
  ResultsStamp s;
  try {
    h5::read_attribute(f, "source_file", s.source_file, file, "/");
    for (auto [name, out] :
         {std::pair{"input_size", &s.input_size}, std::pair{"input_mtime_ns", &s.input_mtime_ns},
          std::pair{"input_hash", &s.input_hash}, std::pair{"options", &s.options}})
      if (h5::has_attribute(f, name)) h5::read_attribute(f, name, *out, file, "/");
  } catch (const std::exception&) {
    H5Fclose(f);
    return std::nullopt;
  }
  H5Fclose(f);
  return s;
}

std::optional<InputStat> stat_input(const std::filesystem::path& input) {
  struct stat st {};
  if (::stat(input.c_str(), &st) != 0) return std::nullopt;
  const long long ns =
      static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  return InputStat{std::to_string(static_cast<long long>(st.st_size)), std::to_string(ns)};
}

std::uint64_t channel_digest(const std::string& path, std::span<const double> x) {
  std::uint64_t h = kHashSeed;
  for (const char c : path)
    h = mix(h, static_cast<unsigned char>(c));
  h = mix(h, x.size());
  constexpr std::size_t kChains = 8;
  std::array<std::uint64_t, kChains> chain{};
  for (std::size_t c = 0; c < kChains; ++c)
    chain[c] = mix(h, c);
  const auto bits = [&x](std::size_t i) {
    std::uint64_t w;
    std::memcpy(&w, &x[i], sizeof w);
    return w;
  };
  std::size_t i = 0;
  for (; i + kChains <= x.size(); i += kChains)
    for (std::size_t c = 0; c < kChains; ++c)
      chain[c] = mix(chain[c], bits(i + c));
  for (; i < x.size(); ++i)
    chain[i % kChains] = mix(chain[i % kChains], bits(i));
  for (const std::uint64_t c : chain)
    h = mix(h, c);
  return h;
}

std::uint64_t combine_hash(std::uint64_t h, std::uint64_t channel_digest) {
  return mix(h, channel_digest);
}

std::string hash_hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace allanlot::io
