// Reading a recording that is still being written (`allanlot watch`, docs/production.md): what
// of it is complete at the moment of a look.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace allanlot::io {

/// The part of a growing recording that a RecordingReader can read now. A text recording is
/// copied up to its last complete line into `dir` under its own file name (a writer's partial
/// last line waits for the next look; the recording itself is only read); the copy is made
/// only when the recording grew since `*bytes_seen` (updated). An HDF5 recording is read in
/// place (its writer appends whole chunks). Returns the path to read, "" when a text recording
/// has not grown. Throws io::Error naming the recording when it cannot be read or the copy
/// cannot be written.
std::string growing_snapshot(const std::string& path, const std::filesystem::path& dir,
                             std::uintmax_t* bytes_seen);

}  // namespace allanlot::io
