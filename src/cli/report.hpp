// `allanlot report OUTDIR [-o report.html]` (docs/cli.md "Command: report"): the command line of
// the HTML report, which src/report/report.hpp writes.
#pragma once

#include "src/cli/cli.hpp"

namespace allanlot::cli {

/// Adds the `report` subcommand to `app` (see cli.hpp, struct Command).
Command add_report_command(CLI::App& app);

}  // namespace allanlot::cli
