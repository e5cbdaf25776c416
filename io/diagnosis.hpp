// The diagnose command's HDF5 output (docs/diagnose.md "Output"): group
// /<channel>/diagnosis of OUT.h5, which may be a new file or an existing one (a results file of
// `analyze`, or an earlier diagnosis), in which case only that group is replaced. What the group
// holds is described once, in io/schema.hpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {

/// Everything stored in /<channel>/diagnosis. Per-tau datasets have one entry per tau of the
/// comparison grid; per-iteration datasets one entry per effect added.
struct DiagnosisRecord {
  std::string channel;  // the channel's path, e.g. "/imu/gyro_x"
  // Per tau.
  std::vector<std::int64_t> m;
  std::vector<double> tau, avar_measured, edf, avar_model_before, avar_model_after;
  std::vector<double> mc_before_lo, mc_before_hi, mc_after_lo, mc_after_hi;
  std::vector<double> z_before, z_after;
  std::vector<std::uint8_t> significant_before, significant_after;
  // Per iteration.
  std::vector<std::string> effect, parameters_json;
  std::vector<double> gap_before, gap_after, delta_ic;
  // Group attributes (numbers and strings), e.g. gap_before, model_after (JSON), report (JSON).
  std::vector<std::pair<std::string, double>> number_attributes;
  std::vector<std::pair<std::string, std::string>> string_attributes;
};

/// Writes `r` to `out` as group /<r.channel>/diagnosis, atomically: a new file is created under
/// a temporary name; an existing file is copied to a temporary name, the group (re)written
/// there, and the copy renamed over `out`. `input` (the recording diagnosed) is never written:
/// io::Error when `out` is the same file. Throws io::Error naming the file on any failure.
void write_diagnosis(const std::filesystem::path& out, const std::filesystem::path& input,
                     const DiagnosisRecord& r);

/// Every /<channel>/diagnosis group of `file` (a diagnose output, or a results file diagnose
/// wrote into), in path order, read through the schema (io/schema.hpp). Datasets a group lacks
/// are left empty. Throws io::Error naming the file and the group on a dataset or attribute of
/// the wrong type.
std::vector<DiagnosisRecord> read_diagnoses(const std::filesystem::path& file);

}  // namespace allanlot::io
