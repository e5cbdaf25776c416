// The plan workflow (docs/cli.md "Command: plan", docs/production.md): how long to record a unit
// so that its noise coefficients are measured to a target precision, or its spec limits are
// decided, with a stated confidence; optionally checked by simulation. The command line
// adds its options and its table; the Python module's plan() takes the JSON.
#pragma once

#include "kernels/plan/length.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace allanlot::workflow {

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
  int threads = 0;
};

/// One length planned: a term of a channel to measure, or one of its limits to decide.
struct PlannedLength {
  std::string key;    // "gyro_x:B", "gyro_x:B<=max"
  std::string label;  // what the table says of it
  kernels::ChannelSpec spec;
  kernels::LengthTarget target;
  double value = 0;                // the coefficient simulated, channel units
  std::optional<double> min, max;  // with a spec: the limits, channel units
  double k = 0;                    // with a spec: the spec's interval quantile
  kernels::LengthPlan plan;
  double share = std::numeric_limits<double>::quiet_NaN();  // the verified share (verify > 0)
};

/// Every length planned, the one that binds (the longest) and the confidence used.
struct Plan {
  std::vector<PlannedLength> lengths;
  std::size_t binding = 0;
  double confidence = 0.0;
};

/// Plans (and, with verify > 0, verifies) every target or limit. Throws UsageError
/// (src/workflow/status.hpp: bad model, target, nothing to plan), spec::Error (a bad spec
/// file, every message) and std::exception for a failed plan.
Plan plan_recording(const PlanOptions& opt);

/// {"duration_s", "binding", "confidence", "per_target": {key: {...}}} (docs/cli.md
/// "Command: plan"): `allanlot plan --json` and the Python module's plan().
nlohmann::ordered_json plan_json(const Plan& plan);

/// A fraction as a percentage with 3 significant digits, "12.5%".
std::string percent_text(double x);

}  // namespace allanlot::workflow
