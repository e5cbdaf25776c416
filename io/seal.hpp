// The seal of the HDF5 files allanlot writes (results files, lot summaries): proof that a file
// is byte for byte what allanlot wrote, checked before the HDF5 library reads a byte of it.
//
// Why: the HDF5 library trusts the bytes it reads; a results file damaged on disk (a bad
// sector, a partial copy, 64 random bytes) can send it into a crash in its global heap, and a
// file edited afterwards (a channel group deleted, a dataset rewritten) opens cleanly and reads
// as complete. Neither may be trusted by resume, nor crash `summarize`, `report` or `export`.
//
// How: each file is created with a 512-byte HDF5 user block (H5Pset_userblock), space at the
// start of the file that the library skips and never writes (the superblock then sits at byte
// 512, where every HDF5 reader looks for it). allanlot builds the whole file in memory, then
// writes the user block, a text header, before the image in one write(2):
//   allanlot-seal 1\n  bytes <size of the file>\n  hash <64-bit FNV-1a of bytes 512..end>\n
// padded with NUL bytes. A file whose header is present but whose size or hash disagree is
// damaged; a file without the header was written by an earlier version (unsealed) and is read
// as before. FNV-1a (Fowler, Noll, Vo) detects change, not an adversary, which is the aim.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

namespace allanlot::io {

/// Size of the user block that holds the seal (HDF5 wants a power of two, at least 512).
inline constexpr std::size_t kSealBytes = 512;

/// The user block that seals `body`, the HDF5 image that follows it in the file (HDF5's file
/// image of a file created with a kSealBytes user block starts after the user block).
std::array<char, kSealBytes> seal_block(std::span<const char> body);

enum class SealState {
  Intact,    // the seal matches: the file is what allanlot wrote
  Unsealed,  // no seal: a file of an earlier version (or not allanlot's)
  Damaged,   // a seal that does not match, or a file too short or unreadable
};

struct SealCheck {
  SealState state = SealState::Unsealed;
  std::string reason;  // for Damaged: what disagrees
};

/// Writes the seal of a sealed file anew after HDF5 edited it in place (diagnose -o into a
/// results file); an unsealed file is left as it is. Throws io::Error on a read or write error.
void reseal_file(const std::filesystem::path& path);

/// Reads `path` and checks its seal.
SealCheck check_seal(const std::filesystem::path& path);

/// Throws io::Error naming `path` when its seal says it is damaged; returns whether it is
/// sealed (false: an unsealed file of an earlier version, read as before).
bool require_intact(const std::filesystem::path& path);

}  // namespace allanlot::io
