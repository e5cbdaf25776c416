// `allanlot plan` (docs/cli.md "Command: plan", docs/production.md): how long to record a unit
// so that its noise coefficients are measured to a target precision, or its spec limits are
// decided, with a stated confidence; optionally checked by simulation.
#pragma once

#include "src/cli/cli.hpp"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::cli {

struct PlanOptions {
  std::string model_path;            // "" = the embedded demo unit (the paper's Table)
  std::string channel = "gyro_x";    // dataset name of a single-channel model
  std::vector<std::string> targets;  // "B=10%", "N=0.02": relative precision per term
  std::string spec_path;             // limits to decide instead of targets
  double margin = 0.2;               // with --spec: the unit's distance inside each limit
  double confidence = 0.95;          // of the targets' intervals; the spec's own with --spec
  bool confidence_given = false;
  int verify = 0;  // simulated recordings of the planned length
  std::uint64_t seed = 1;
  double max_duration_s = 30 * 86400.0;  // the longest record searched
  bool json = false;
  int threads = 0;
};

/// Returns the exit status: 0 planned (and verified), 1 a target not reached within
/// --max-duration, 2 usage error (bad model, spec or target).
int run_plan(const PlanOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `plan` subcommand to `app` (see cli.hpp, struct Command).
Command add_plan_command(CLI::App& app);

}  // namespace allanlot::cli
