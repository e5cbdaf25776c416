// `allanlot hat` (docs/cli.md "Command: hat"): the three-cornered hat of three clocks from the
// recordings of their pairwise differences AB, BC, CA: each clock's Allan deviation with its
// interval, written as one results file (docs/formats.md "Results files of hat and codev").
#pragma once

#include "src/cli/cli.hpp"
#include "src/cli/paired.hpp"

#include <iosfwd>

namespace allanlot::cli {

/// Runs the command; returns the exit status of docs/cli.md (0, 1 or 2).
int run_hat(const PairedOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `hat` subcommand to `app` (see cli.hpp, struct Command).
Command add_hat_command(CLI::App& app);

}  // namespace allanlot::cli
