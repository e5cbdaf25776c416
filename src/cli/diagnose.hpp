// `allanlot diagnose` (docs/diagnose.md): where a noise model disagrees with a
// measured channel, which effect is missing, and the corrected model
// (kernels/diagnose/diagnose.hpp).
#pragma once

#include "src/cli/cli.hpp"
#include "src/workflow/diagnose.hpp"

#include <iosfwd>

namespace allanlot::cli {

/// The workflow's request (src/workflow/diagnose.hpp) and how to print its outcome.
struct DiagnoseOptions : workflow::DiagnoseRequest {
  bool json = false;  // print the JSON object of docs/diagnose.md instead of the report
};

/// Exit status: 0 diagnosed (whatever was found); 1 the diagnosis could not be made or written
/// (unreadable input or channel, record too short, output not writable); 2 usage error (bad
/// options, bad model file, channel missing or ambiguous, units that differ from the model's,
/// -o naming the input).
int run_diagnose(const DiagnoseOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `diagnose` subcommand to `app`.
Command add_diagnose_command(CLI::App& app);

}  // namespace allanlot::cli
