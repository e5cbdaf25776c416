// `allanlot convert INPUT... -o DIR` (docs/cli.md "Command: convert"): each input recording,
// text or HDF5, written as an HDF5 recording in the canonical layout, so that analysing the
// converted file gives the same results as analysing the input.
#pragma once

#include "src/cli/cli.hpp"

namespace allanlot::cli {

/// Adds the `convert` subcommand to `app` (see cli.hpp, struct Command).
Command add_convert_command(CLI::App& app);

}  // namespace allanlot::cli
