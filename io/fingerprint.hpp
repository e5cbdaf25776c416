// Resume support for `analyze` (issue "Lots at scale"): what a results file records about the
// input it was made from and the options it was made with, so that rerunning the same command
// skips recordings whose complete results are present and current.
//
// The stamp is four root attributes of the results file, written by analyze with the others:
//   input_size      bytes of the input file
//   input_mtime_ns  its modification time (ns since the epoch)
//   input_hash      a 64-bit hash of the samples of every channel analysed, as read (hex)
//   options         the options that change results (statistics, taus, confidence, channel
//                   glob, fit and PSD switches, tool version), canonically written
// A results file is current when its options equal the run's and the input has the same size
// and modification time; when only the time differs (a copy, a touch), the content hash
// decides. The hash is for detecting change, not an adversary: a word-wise multiply-xorshift
// mix (in the spirit of SplitMix64, Steele et al., OOPSLA 2014) of the IEEE bits of each
// sample and of each channel's path and length, so reordering or editing any sample changes it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

namespace allanlot::io {

/// What a results file says about its input (empty strings where an attribute is absent, e.g.
/// a results file written before resume existed).
struct ResultsStamp {
  std::string source_file;
  std::string input_size;
  std::string input_mtime_ns;
  std::string input_hash;
  std::string options;
};

/// The stamp of a complete results file, or nullopt when it does not exist or cannot be read
/// (a damaged results file is simply redone).
std::optional<ResultsStamp> read_results_stamp(const std::filesystem::path& results);

/// Size and modification time of an input file as the stamp writes them; nullopt when the file
/// cannot be stat'ed.
struct InputStat {
  std::string size;
  std::string mtime_ns;
};
std::optional<InputStat> stat_input(const std::filesystem::path& input);

/// Incremental content hash (see the file comment). Start from kHashSeed.
inline constexpr std::uint64_t kHashSeed = 0x6a09e667f3bcc908ULL;
std::uint64_t hash_channel(std::uint64_t h, const std::string& path, std::span<const double> x);
std::string hash_hex(std::uint64_t h);

}  // namespace allanlot::io
