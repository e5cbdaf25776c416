// `allanlot summarize OUTDIR` (docs/cli.md "Command: summarize"): its options; the work is the
// workflow's (src/workflow/summarize.hpp).
#pragma once

#include "src/cli/cli.hpp"

namespace allanlot::cli {

/// Adds the `summarize` subcommand to `app` (see cli.hpp, struct Command).
Command add_summarize_command(CLI::App& app);

}  // namespace allanlot::cli
