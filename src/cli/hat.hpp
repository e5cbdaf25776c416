// `allanlot hat` (docs/cli.md "Command: hat"): the N-cornered hat of N >= 3 clocks from the
// recordings of their pairwise differences: AB BC CA (three clocks, the form without --clocks),
// or with --clocks A,B,C,D,... the N(N-1)/2 pairs in pair order AB AC AD BC BD CD; each clock's
// Allan deviation with its interval, written as one results file (docs/formats.md "Results
// files of hat and codev").
#pragma once

#include "src/cli/cli.hpp"
#include "src/cli/paired.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

/// The three-cornered hat of AB BC CA; returns the exit status of docs/cli.md (0, 1 or 2).
int run_hat(const PairedOptions& opt, std::ostream& out, std::ostream& err);

/// The N-cornered hat of the clocks `clocks` (N >= 3) from opt.inputs, the N(N-1)/2 pairs in
/// pair order (hat_pair_names); the exit status as above.
int run_hat(const PairedOptions& opt, const std::vector<std::string>& clocks, std::ostream& out,
            std::ostream& err);

/// The names of --clocks "A,B,C": CLI::ValidationError (a usage error) for fewer than 3, an
/// empty or repeated name, or a character other than letters, digits, '_' and '.'.
std::vector<std::string> hat_clock_names(const std::string& list);

/// The pairs' names in pair order: "AB", "AC", ... when every name is one character, else
/// "H1-H2", "H1-Cs", ...
std::vector<std::string> hat_pair_names(const std::vector<std::string>& clocks);

/// Adds the `hat` subcommand to `app` (see cli.hpp, struct Command).
Command add_hat_command(CLI::App& app);

}  // namespace allanlot::cli
