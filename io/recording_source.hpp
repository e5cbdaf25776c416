// The recording-source interface behind io::RecordingReader (docs/formats.md "Input
// recordings"): each format is a source that describes a recording (channels, rates, units,
// device id) and reads a channel's samples, and says whether it recognises a file. The formats
// are tried in the order of one list (io/recording_source.cpp); a new format is one new file
// pair and one line in that list.
#pragma once

#include "io/recording.hpp"

#include <memory>
#include <span>
#include <string>

namespace allanlot::io {

class RecordingSource {
public:
  virtual ~RecordingSource() = default;
  /// What discovery found: channels, problems, device id, facts, notes.
  virtual RecordingInfo describe() const = 0;
  /// A whole channel of describe(), converted to double physical values (raw * scale +
  /// offset). Throws io::Error naming file and channel on a read failure.
  virtual kernels::LargeVector<double> read(const ChannelInfo& channel,
                                            std::size_t chunk) const = 0;
};

/// One input format.
struct SourceFormat {
  const char* name;  // "HDF5", "text", ...
  /// Whether the file (or folder) is this format's, by its first bytes or name; cheap, reads
  /// at most a block, never throws.
  bool (*recognises)(const std::string& path);
  /// Throws io::UsageError when the command line lacks what the file needs (reads only its
  /// head); nullptr when the format needs nothing from it.
  void (*check_options)(const std::string& path, const InputOptions& options);
  /// Opens and describes the recording; throws io::Error naming the file.
  std::unique_ptr<RecordingSource> (*open)(const std::string& path, const InputOptions& options);
};

/// The formats in the order they are tried: the first that recognises a file reads it.
std::span<const SourceFormat> source_formats();

/// The format that reads `path`, nullptr when none recognises it.
const SourceFormat* find_source_format(const std::string& path);

/// The channel's unit in the one vocabulary (kernels/model/units.hpp): "dps" is deg/s, "m/s2"
/// m/s^2; a clock's phase in ns or frequency in ppb is scaled to s or 1, its frequency in Hz
/// made fractional with --nominal-frequency (io::UsageError naming `file` and the channel
/// without it). Units outside the vocabulary stay as written (analyze warns about them).
void in_canonical_units(ChannelInfo& ch, const InputOptions& options, const std::string& file);

/// Raw samples to the channel's canonical units: the file's scale and offset, the unit's factor,
/// and a frequency in Hz made fractional (y = (f - F) / F).
void to_physical(const ChannelInfo& channel, std::span<double> samples);

/// The reason a channel in `units` (a frequency in Hz) cannot be read without --nominal-frequency.
std::string needs_nominal_frequency(const std::string& units);

}  // namespace allanlot::io
