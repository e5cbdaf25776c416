// Reading a recording that is still being written (`allanlot watch`, docs/production.md): what
// of it is complete at the moment of a look.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace allanlot::io {

/// The part of a growing recording that a RecordingReader can read now, "" when it has not
/// grown since `*bytes_seen` (its size, updated). A text recording is copied up to its last
/// complete line into `dir` under its own file name (a writer's partial last line waits for the
/// next look). An HDF5 recording that a writer extends in SWMR mode (single writer, multiple
/// readers; HDF5 1.10) is opened with SWMR read access and its objects copied into `dir` as they
/// stand (a reader without SWMR access would be refused); any other HDF5 file is read in place.
/// The recording itself is only read. Throws io::Error naming the recording when it cannot be
/// read or the copy cannot be written.
std::string growing_snapshot(const std::string& path, const std::filesystem::path& dir,
                             std::uintmax_t* bytes_seen);

}  // namespace allanlot::io
