// `allanlot analyze` (docs/cli.md "Command: analyze"): its options, its printing (the progress
// line, each unit's tables, the closing lines) and its signals. The batch over recordings is the
// workflow's (src/workflow/analyze.hpp).
#pragma once

#include "src/cli/cli.hpp"
#include "src/workflow/analyze.hpp"

#include <iosfwd>

namespace allanlot::cli {

using workflow::AnalyzeOptions;

/// Runs the analysis and returns the exit status of docs/cli.md (0, 1, 2 or 128 + a signal).
/// Failures are named on `err` with file, dataset and reason; the closing summary goes to `out`.
int run_analyze(const AnalyzeOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `analyze` subcommand to `app` (see cli.hpp, struct Command).
Command add_analyze_command(CLI::App& app);

}  // namespace allanlot::cli
