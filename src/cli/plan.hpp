// `allanlot plan` (docs/cli.md "Command: plan", docs/production.md): the options and the printed
// table of the plan workflow (src/workflow/plan.hpp).
#pragma once

#include "src/cli/cli.hpp"
#include "src/workflow/plan.hpp"

#include <iosfwd>

namespace allanlot::cli {

struct PlanOptions : workflow::PlanOptions {
  bool json = false;  // print the JSON of workflow::plan_json instead of the table
};

/// Returns the exit status: 0 planned (and verified), 1 a target not reached within
/// --max-duration, 2 usage error (bad model, spec or target).
int run_plan(const PlanOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `plan` subcommand to `app` (see cli.hpp, struct Command).
Command add_plan_command(CLI::App& app);

}  // namespace allanlot::cli
