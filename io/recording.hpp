// Input recordings (docs/formats.md "Input recordings"): channel discovery and chunked
// reading of one unit's recording in any format of io/recording_source.hpp (HDF5, text, ...),
// and the writer that `allanlot simulate` and `allanlot convert` use for the HDF5 layout.
#pragma once

#include "io/input_options.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/quality/quality.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// One channel: a 1-D integer or floating dataset with a `sample_rate_hz` attribute on itself
/// or its nearest ancestor group. Optional attributes are looked up the same way.
struct ChannelInfo {
  std::string path;             // dataset path in the file, e.g. "/imu/gyro_x"
  std::string units;            // `units` attribute, "" when absent
  double sample_rate_hz = 0.0;  // in [kMinSampleRateHz, kMaxSampleRateHz]
  double scale = 1.0;           // physical = raw * scale + offset
  double offset = 0.0;
  double nominal_hz = 0.0;  // > 0: a frequency in Hz, read as (physical - F) / F (units.hpp)
  bool has_scale = false;   // a `scale` attribute was found
  kernels::DataType data_type = kernels::DataType::Rate;
  bool data_type_default = false;  // neither the file nor --data-type said: rate by default
  std::int64_t n_samples = 0;
  std::string storage_type;              // "float64", "float32", "int16", ... as stored
  kernels::TimeStampCounts time_stamps;  // a text recording's time column (quality screen)
};

/// The sample rates allanlot analyses. The statistics are sums of squared phase differences in
/// seconds (x = y / rate_hz for rate data), so tau0^2 = 1 / rate^2 must stay well inside
/// double's range together with the taus of a record (m up to 10^9): from one sample in 30
/// years to 1 THz. Beyond, tau^2 under- or overflows and every deviation would be 0, inf or
/// NaN; a channel with such a rate is a named problem instead.
inline constexpr double kMinSampleRateHz = 1e-9;
inline constexpr double kMaxSampleRateHz = 1e12;
/// The most samples a channel may declare: 2^60 doubles are 2^63 bytes, so byte counts of any
/// channel fit 64 bits (a chunked dataset never written declares any length in a few bytes).
inline constexpr std::uint64_t kMaxSamples = std::uint64_t{1} << 60;

/// A dataset that looks like a channel (it is in the scope of a sample_rate_hz attribute)
/// but cannot be analysed; the reason names what is wrong.
struct ChannelProblem {
  std::string path;
  std::string reason;
};

/// What discovery found in one file.
struct RecordingInfo {
  std::string file;       // the path as given
  std::string device_id;  // root attribute `device_id`, else the file's stem
  std::vector<ChannelInfo> channels;
  std::vector<ChannelProblem> problems;
  /// What was inferred from a text recording, as (attribute, value): its file name, layout,
  /// time column and unit, step, missing samples, jitter. Empty for HDF5.
  std::vector<std::pair<std::string, std::string>> facts;
  std::vector<std::string> notes;  // what a user should know (missing samples, jitter)
};

/// The one matching rule of channel globs (--channels, --exclude-channels, --units, spec files):
/// an empty glob matches every channel; otherwise the glob (fnmatch) must match the channel's
/// path (`/imu/gyro_x`) or its name (`gyro_x`).
bool channel_glob_matches(const std::string& glob, const std::string& path);

/// True when `path` is read as a text recording: not named *.h5 / *.hdf5, and named like one
/// (.txt .dat .csv .tsv, optionally .gz), gzip-compressed, or text in its first block.
bool is_text_recording(const std::string& path);

/// Throws io::UsageError when `path` is a text recording that needs an option `options` lacks
/// (reads only its head), or an HDF5 recording with a channel in Hz when `options` has no
/// nominal frequency (reads its attributes only). The commands call it for every input before any
/// work, so that a missing option is a usage error and never a night of failed inputs.
void check_input_options(const std::string& path, const InputOptions& options);

class RecordingSource;  // io/recording_source.hpp

/// Opens a recording read-only (inputs are never modified) and discovers its channels; a text
/// recording is parsed whole here. `options` (--data-type and the text options) apply to
/// every channel. Throws io::Error naming the file when it cannot be opened or parsed,
/// io::UsageError when a text recording needs an option that was not given.
class RecordingReader {
public:
  explicit RecordingReader(const std::string& path, const InputOptions& options = {});
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  const RecordingInfo& info() const { return info_; }

  /// Reads a whole channel in chunks of `chunk` samples, converted to double physical values
  /// (raw * scale + offset), in page-fault-cheap storage (kernels/common/large_vector.hpp).
  /// Throws io::Error naming file and dataset on a read failure.
  kernels::LargeVector<double> read(const ChannelInfo& channel, std::size_t chunk = 1 << 20) const;

private:
  std::unique_ptr<RecordingSource> source_;  // the format that recognised the file
  RecordingInfo info_;
};

/// One channel to write with write_recording.
struct ChannelData {
  std::string name;  // dataset name under the group, e.g. "gyro_x" (or "imu/gyro_x")
  std::string units;
  std::span<const double> samples;
};

/// Attributes of a channel beyond its units, for add_channel.
struct ChannelAttributes {
  std::string data_type;        // `data_type` ("rate", "phase"); "" writes none
  double sample_rate_hz = 0.0;  // `sample_rate_hz` on the dataset itself; 0 writes none
};

/// Incremental writer of a recording in the layout `allanlot simulate` produces:
/// root attribute device_id, group /<group> with sample_rate_hz (none when 0; group "" is the
/// root), one float64 dataset per channel with a `units` attribute. The file is written under
/// a temporary name and renamed by commit(), so a recording appears only complete; without
/// commit() nothing is left.
class RecordingWriter {
public:
  /// Datasets added after this are chunked and compressed (shuffle, then deflate `level`).
  void set_deflate(int level);
  /// Adds a string attribute to the dataset of a channel already added.
  void add_channel_attribute(const std::string& name, const std::string& attr,
                             const std::string& value);
  RecordingWriter(const std::string& path, const std::string& device_id, double sample_rate_hz,
                  const std::string& group = "imu");
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  void add_channel(const ChannelData& channel, const ChannelAttributes& attributes = {});
  /// Adds a string attribute to the root (e.g. the model the data were simulated from).
  void add_root_attribute(const std::string& name, const std::string& value);
  void commit();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reduces a device id to [A-Za-z0-9._-] and the letters of other scripts (UTF-8, see
/// io/utf8.hpp name_letter_length; every other byte becomes '_', a leading '.' becomes '_'),
/// so that OUTDIR/<id>.allan.h5 can never name a path outside OUTDIR, and ids in Cyrillic or
/// CJK do not all reduce to the same run of '_'.
std::string sanitize_device_id(const std::string& id);

}  // namespace allanlot::io
