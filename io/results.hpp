// Results files (CONTRACT "Results file layout") and the lot summary ("Lot summary").
#pragma once

#include "kernels/stats.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// Everything written for one channel.
struct ChannelResult {
  std::string path;  // the channel's own path, e.g. "/imu/gyro_x"
  std::string units;
  double sample_rate_hz = 0.0;
  std::int64_t n_samples = 0;
  std::int64_t n_gaps = 0;
  std::string data_type = "rate";  // "rate" or "phase"
  std::string status = "ok";       // "ok" or "failed: <reason>"
  /// (statistic name, result) in the order computed; written to allan/<name>/.
  std::vector<std::pair<std::string, kernels::StatResult>> stats;
};

/// One results file: one input recording.
struct RecordingResult {
  std::string device_id;  // as found in the input (sanitized only for the file name)
  std::string source_file;
  std::string tool_version;
  std::string created_utc;
  std::string command_line;
  /// Further root attributes: analysis options, thread count, git revision.
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<ChannelResult> channels;
};

/// Writes `r` to `path` through a temporary file renamed into place: the results file is
/// complete or absent. Throws io::Error naming the path on failure.
void write_results(const std::filesystem::path& path, const RecordingResult& r);

/// Reads a results file back (root attributes, channels, statistics).
RecordingResult read_results(const std::filesystem::path& path);

/// One row of the lot summary: one (device, channel), or one failed input (channel empty).
struct SummaryRow {
  std::string device_id;
  std::string channel;
  std::string units;
  std::int64_t n_samples = 0;
  std::string status = "ok";
  std::string source_file;
};

/// Writes OUTDIR/lot_summary.csv and OUTDIR/lot_summary.h5 (compound dataset /summary), each
/// atomically.
void write_lot_summary(const std::filesystem::path& outdir, const std::vector<SummaryRow>& rows);

/// Reads the /summary compound dataset of a lot_summary.h5.
std::vector<SummaryRow> read_lot_summary(const std::filesystem::path& h5_path);

/// The summary rows of one recording's results.
std::vector<SummaryRow> summary_rows(const RecordingResult& r);

}  // namespace allanlot::io
