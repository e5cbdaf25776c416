// The lot summary (docs/formats.md "Lot summary"): rebuilt from the complete results files in
// OUTDIR plus the failures of the current run, written as lot_summary.csv / lot_summary.h5, with
// pass/fail against a spec file (src/lot/spec.hpp), lot statistics per channel kind and term
// (lot_statistics.csv, /statistics) and outlier units (src/lot/statistics.hpp). Shared by `analyze`
// (after its inputs) and `summarize` (alone, e.g. as a Slurm merge job). docs/formats.md describes
// the columns.
#pragma once

#include "io/results.hpp"
#include "src/lot/spec.hpp"
#include "src/lot/statistics.hpp"

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::lot {

struct LotOptions {
  std::filesystem::path spec_path;  // --spec: limits per channel kind and term ("" = none)
  // The spec already loaded from spec_path (load_spec), so that a command can refuse a bad spec
  // before it reads anything; when null and spec_path is set, write_lot loads it.
  const spec::Spec* spec = nullptr;
  std::filesystem::path manifest;  // summarize --manifest: entries without results are failed
  bool quiet = false;              // errors only: no lot overview on `out`, no warnings
};

/// What write_lot did, for the caller's exit status and messages.
struct KindCounts {
  std::string channel;  // channel path, e.g. "/imu/gyro_x"
  std::size_t pass = 0, fail = 0, undecided = 0, no_spec = 0, no_data = 0, outliers = 0;
};
struct LotOverview {
  std::size_t n_units = 0;          // distinct device ids
  std::size_t n_rows = 0;           // rows written
  std::size_t n_failed_inputs = 0;  // rows of inputs without results (channel empty)
  std::size_t n_failed_channels = 0;
  std::size_t n_missing = 0;  // manifest entries without a results file (also in n_failed_inputs)
  bool spec = false;          // a spec was applied
  std::vector<KindCounts> kinds;      // per channel kind, sorted by path
  std::vector<std::string> outliers;  // "device:channel (N z=+5.2)"
  std::vector<std::string> quality;   // "device:channel (spikes;saturation)": flags raised
  // Per-unit verdicts (spec::judge_units): units passing, and "device (detail)" of the others.
  std::size_t units_pass = 0;
  std::vector<std::string> units_fail, units_undecided, units_other;
};

/// The summary rows of every complete results file (*.allan.h5, not hidden) in `outdir`, in
/// file-name order, read with io::read_summary_results (no per-tau arrays). An unreadable or
/// damaged results file is named on `err` and becomes one failed row (counted in
/// `*unreadable` when given).
std::vector<io::SummaryRow> rows_from_outdir(const std::filesystem::path& outdir, std::ostream& err,
                                             std::size_t* unreadable = nullptr);

/// The rows `failed: no results file` for the manifest's entries (trimmed lines, blank and
/// `#` lines skipped, relative paths relative to the manifest, as analyze reads a manifest)
/// whose absolute path is no row's source_file. Throws std::runtime_error naming the manifest
/// when it cannot be read.
std::vector<io::SummaryRow> manifest_failures(const std::filesystem::path& manifest,
                                              const std::vector<io::SummaryRow>& rows);

/// Writes the lot summary of `rows` into `outdir` (atomically): adds the manifest's missing
/// entries, applies the spec, computes the statistics and outliers, writes lot_summary.csv,
/// lot_statistics.csv and lot_summary.h5, and prints a short overview on `out` unless
/// opt.quiet. A spec rule that matches no channel is a warning on `err` (none when opt.quiet).
/// Throws on a bad spec file (spec::Error), an unreadable manifest, or a write failure
/// (std::exception naming the file).
LotOverview write_lot(const std::filesystem::path& outdir, std::vector<io::SummaryRow> rows,
                      const LotOptions& opt, std::ostream& out, std::ostream& err);

}  // namespace allanlot::lot
