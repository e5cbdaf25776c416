// Resume support for `analyze` (docs/lots-and-slurm.md "Running a lot", Resume): what a results
// file records about the input it was made from and the options it was made with, so that rerunning
// the same command skips recordings whose complete results are present and current.
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
// Each channel has a digest of its own (its samples mixed in eight interleaved chains, sample i
// into chain i mod 8, then the chains into one: eight independent multiply chains run about
// five times faster than one), and the channels' digests are chained in channel order, so that
// channels read and analysed in parallel hash as the sequential read.
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

/// The content hash (see the file comment): from kHashSeed, combine_hash of each channel's
/// channel_digest in channel order.
inline constexpr std::uint64_t kHashSeed = 0x6a09e667f3bcc908ULL;
std::uint64_t channel_digest(const std::string& path, std::span<const double> x);
std::uint64_t combine_hash(std::uint64_t h, std::uint64_t channel_digest);
std::string hash_hex(std::uint64_t h);

}  // namespace allanlot::io
