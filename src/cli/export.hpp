// `allanlot export RESULTS... --format stable32|csv [-o FILE|DIR]`: the Allan-family tables of
// results files for other tools. `stable32` prints, per unit, channel and statistic, the table
// Stable32 1.60 prints for a run (io/stable32_table.hpp), one file per table when -o is a
// directory, so that the two can be diffed; `csv` is one tidy table (one row per tau) for
// spreadsheets and pandas; `readouts` one tidy table of the fit's read-outs (N at 1 s also as
// ARW/VRW, bias instability with its tau, K at 3 s; one row per channel and read-out);
// `kalibr`, `openvins` and `vins` one IMU's noise for those tools (src/cli/export_filter.hpp).
#pragma once

#include "kernels/allan/stats.hpp"
#include "src/cli/cli.hpp"
#include "src/cli/export_filter.hpp"
#include "src/workflow/inputs.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

enum class ExportFormat { Stable32, Csv, Readouts, Kalibr, OpenVins, Vins };

struct ExportOptions {
  std::vector<std::filesystem::path> inputs;  // results files, or directories of them
  ExportFormat format = ExportFormat::Csv;
  std::filesystem::path output;            // "" = standard output; a directory: one file per table
  std::vector<std::string> stats;          // only these statistics (empty = all)
  workflow::ChannelSelection channels;     // --channels, --exclude-channels (all by default)
  AxisCombine combine = AxisCombine::Max;  // --combine: the kalibr/openvins/vins axes
};

/// Writes the tables of every readable results file, in sorted file order. Returns 0; 1 when
/// some inputs could not be read (each named on `err`; the others are exported); 2 usage
/// error (no results file, none readable, unknown statistic, --stats with readouts, output not
/// writable).
int run_export(const ExportOptions& opt, std::ostream& out, std::ostream& err);

/// The name of one table's file in an -o directory: device, channel and statistic, e.g.
/// "phasedat.clock_x.oadev.txt", reduced to [A-Za-z0-9._-] like results file names.
std::string stable32_file_name(const std::string& device_id, const std::string& channel,
                               const std::string& stat);

/// Adds the `export` subcommand to `app` (see cli.hpp, struct Command).
Command add_export_command(CLI::App& app);

}  // namespace allanlot::cli
