// `allanlot codev` (docs/cli.md "Command: codev"): the Groslambert codeviation of two
// recordings measured against the same reference, with its interval, written as one results
// file (docs/formats.md "Results files of hat and codev").
#pragma once

#include "src/cli/cli.hpp"
#include "src/cli/paired.hpp"

#include <iosfwd>

namespace allanlot::cli {

/// Runs the command; returns the exit status of docs/cli.md (0, 1 or 2).
int run_codev(const PairedOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `codev` subcommand to `app` (see cli.hpp, struct Command).
Command add_codev_command(CLI::App& app);

}  // namespace allanlot::cli
