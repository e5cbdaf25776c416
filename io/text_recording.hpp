// Text recordings (docs/formats.md "Text recordings"): single-column files (Stable32,
// AllanTools: one value a line, an optional leading time tag) and CSV/TSV files with a header
// (one channel per numeric column, an optional time column), plain or gzip-compressed. Read
// in one streaming pass into the channels io::RecordingReader hands to the pipeline.
#pragma once

#include "io/input_options.hpp"
#include "kernels/quality/quality.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

struct TextChannel {
  std::string path;  // "/data" for a single column, "/<column name>" for a CSV column
  std::string units;
  std::vector<double> samples;  // NaN where a sample is missing
};

/// Channels in the order of their paths, as the HDF5 reader finds them.
struct TextRecording {
  std::string device_id;  // the file name without its data extensions
  double sample_rate_hz = 0.0;
  std::optional<kernels::DataType> data_type;  // nullopt: nobody said (rate by default)
  std::vector<TextChannel> channels;
  /// What was inferred, as (attribute, value): the source file name, the layout, the time
  /// column, its unit and how it was chosen, the step, the missing samples, the jitter.
  std::vector<std::pair<std::string, std::string>> facts;
  std::vector<std::string> notes;        // what a user should know (timing jitter)
  kernels::TimeStampCounts time_stamps;  // stamps repeated or out of order (time_axis.hpp)
};

/// The names of TextRecording::facts: `convert` writes them as root attributes, and the HDF5
/// reader reads them back, so that a converted file's results say what the text's did.
inline constexpr const char* kTextFactNames[] = {
    "source_file_name", "source_layout", "source_column",        "time_column",
    "time_unit",        "time_step_s",   "time_missing_samples", "time_jitter_rms_s"};

/// True for the names of text recordings: .txt .dat .csv .tsv, each optionally .gz, any case.
bool is_text_name(const std::string& path);

/// The file name without its data extensions: `unit7.csv.gz` -> `unit7`.
std::string text_device_id(const std::string& path);

/// Throws io::UsageError when the command line lacks what `path` needs (reads only its head).
void check_text_options(const std::string& path, const InputOptions& opt);

/// Reads a whole text recording. Throws io::UsageError as check_text_options, io::Error
/// naming file, line and column for a malformed line.
TextRecording read_text_recording(const std::string& path, const InputOptions& opt);

}  // namespace allanlot::io
