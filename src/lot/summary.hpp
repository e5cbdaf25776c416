// The lot summary (docs/formats.md "Lot summary"): rebuilt from the complete results files in
// OUTDIR plus the failures of the current run, written as lot_summary.csv / lot_summary.h5, with
// pass/fail against a spec file (src/spec.hpp), lot statistics per channel kind and term
// (lot_statistics.csv, /statistics) and outlier units. Shared by `analyze` (after its inputs)
// and `summarize` (alone, e.g. as a Slurm merge job). docs/formats.md describes the columns.
#pragma once

#include "io/results.hpp"

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

namespace allanlot::cli {

struct LotOptions {
  std::filesystem::path spec_path;  // --spec: limits per channel kind and term ("" = none)
  std::filesystem::path manifest;   // summarize --manifest: entries without results are failed
  bool quiet = false;               // no lot overview on `out`
};

/// Outlier rule: the modified z-score of Iglewicz & Hoaglin (1993, "How to Detect and Handle
/// Outliers", ch. 3), M = (x - median) / (1.4826 MAD), |M| > 3.5 flags an outlier, with one
/// change: the scale is sqrt((1.4826 MAD)^2 + sigma_i^2), sigma_i the unit's own 1-sigma
/// uncertainty of the coefficient. Median and MAD have a 50 % breakdown point, so the planted
/// outlier cannot hide itself by inflating the scale as it would with mean and standard
/// deviation. 1.4826 = 1 / Phi^-1(3/4) makes 1.4826 MAD estimate sigma for normal data; 3.5 is
/// the cut-off Iglewicz & Hoaglin recommend (P(|Z| > 3.5) = 4.7e-4: about 1 false flag in 2000
/// units of a large normal lot). Why sigma_i: in a small lot the MAD can come out far below the
/// units' own measurement uncertainty by chance (seen on a simulated lot of 8: B of gyro_z with
/// MAD-based spread 0.07 deg/h while each unit's B had sigma 0.3 to 0.9 deg/h), and a unit whose
/// term is undetected (value 0, sigma 0.86) was then "10 spreads" low although it was within
/// one of its own sigmas of the median. A deviation smaller than the unit's own uncertainty is
/// no evidence of anything; with sigma_i << spread the rule is Iglewicz & Hoaglin's.
inline constexpr double kMadToSigma = 1.4826;
inline constexpr double kOutlierZ = 3.5;
/// Below 5 units the scale is too coarse to call anyone an outlier: with 3 or 4 values the
/// MAD is set by one or two deviations, often small by chance, and the rule would flag
/// ordinary units far more often than the 1 in 2000 it is calibrated for.
inline constexpr std::size_t kMinUnitsForOutliers = 5;
// A term is also judged only when at least half of its units detect it (see lot_statistics).

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
};

/// The summary rows of every complete results file (*.allan.h5, not hidden) in `outdir`, in
/// file-name order, read with io::read_summary_results (no per-tau arrays). An unreadable
/// results file is skipped with a warning on `err`.
std::vector<io::SummaryRow> rows_from_outdir(const std::filesystem::path& outdir,
                                             std::ostream& err);

/// The rows `failed: no results file` for the manifest's entries (trimmed lines, blank and
/// `#` lines skipped, relative paths relative to the manifest, as analyze reads a manifest)
/// whose absolute path is no row's source_file. Throws std::runtime_error naming the manifest
/// when it cannot be read.
std::vector<io::SummaryRow> manifest_failures(const std::filesystem::path& manifest,
                                              const std::vector<io::SummaryRow>& rows);

/// The p-quantile (0 <= p <= 1) of ascending `sorted` (non-empty) by linear interpolation
/// between order statistics, x[floor(h)] + (h - floor(h)) (x[floor(h)+1] - x[floor(h)]) with
/// h = (n - 1) p: Hyndman & Fan (1996) definition 7, the default of R and NumPy, so the numbers
/// can be checked with either.
double quantile_sorted(std::span<const double> sorted, double p);

/// Lot statistics per (channel path, term, datasheet unit) over the rows with status ok and a
/// finite value, sorted by channel path then R, K, B, N, Q; sets each row's outlier and
/// outlier_terms by the rule above: only in groups of >= 5 units of which at least half detect
/// the term, and never where both the MAD and the unit's sigma are 0.
std::vector<io::StatisticsRow> lot_statistics(std::vector<io::SummaryRow>& rows);

/// Writes the lot summary of `rows` into `outdir` (atomically): adds the manifest's missing
/// entries, applies the spec, computes the statistics and outliers, writes lot_summary.csv,
/// lot_statistics.csv and lot_summary.h5, and prints a short overview on `out` unless
/// opt.quiet. A spec rule that matches no channel is a warning on `err`. Throws on a bad spec
/// file (spec::Error), an unreadable manifest, or a write failure (std::exception naming the
/// file).
LotOverview write_lot(const std::filesystem::path& outdir, std::vector<io::SummaryRow> rows,
                      const LotOptions& opt, std::ostream& out, std::ostream& err);

}  // namespace allanlot::cli
