// `allanlot export RESULTS... --format stable32|csv [-o FILE]`: the Allan-family tables of
// results files for other tools. `stable32` prints, per unit, channel and statistic, a block
// with the columns and number format of Stable32 1.60's run tables (AF, Tau, #, Alpha,
// Min Sigma, Sigma, Max Sigma; header lines start with '#'), so that the two can be compared
// line by line; `csv` is one tidy table (one row per tau) for spreadsheets and pandas.
#pragma once

#include "kernels/allan/stats.hpp"
#include "src/cli/cli.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

enum class ExportFormat { Stable32, Csv };

struct ExportOptions {
  std::vector<std::filesystem::path> inputs;  // results files, or directories of them
  ExportFormat format = ExportFormat::Csv;
  std::filesystem::path output;    // "" = standard output
  std::vector<std::string> stats;  // only these statistics (empty = all)
  std::string channels_glob;       // only channels whose path or name matches ("" = all)
};

/// Writes the tables of every readable results file, in sorted file order. Returns 0; 1 when
/// some inputs could not be read (each named on `err`; the others are exported); 2 usage
/// error (no results file, none readable, unknown statistic, output not writable).
int run_export(const ExportOptions& opt, std::ostream& out, std::ostream& err);

/// The Stable32-style table of one statistic (header lines and rows), exposed for tests.
/// Without confidence intervals (confidence 0) Min and Max Sigma are printed as 0, as
/// Stable32 does for a run without them.
std::string stable32_block(const std::string& device_id, const std::string& channel,
                           const std::string& units, const std::string& stat,
                           const kernels::StatResult& s);

/// Adds the `export` subcommand to `app` (see cli.hpp, struct Command).
Command add_export_command(CLI::App& app);

}  // namespace allanlot::cli
