// The input options as a caller gives them (docs/cli.md "Input options": --data-type,
// --sample-rate or --tau0, --time-unit, --units, --nominal-frequency) and their check into the
// io::InputOptions the readers take; the command line's options and the Python module's
// arguments both end here.
#pragma once

#include "io/input_options.hpp"
#include "src/workflow/status.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace allanlot::workflow {

/// The options as given, before they are checked.
struct InputArgs {
  std::string data_type, time_unit;
  std::vector<std::string> units;  // --units [GLOB=]UNIT,... as given
  double sample_rate_hz = 0.0, tau0_s = 0.0, nominal_frequency_hz = 0.0;
  io::InputOptions options;
};

/// A usage error that names the option at fault; what() is "OPTION: MESSAGE".
struct OptionError : UsageError {
  OptionError(const std::string& name, const std::string& text)
      : UsageError(name + ": " + text), option(name), message(text) {}
  std::string option, message;
};

/// The checked options; throws OptionError naming the option that is wrong. A text recording's
/// samples are bounded by half of the machine's memory, as analyze bounds them by default.
io::InputOptions checked_input_options(const InputArgs& args);

/// This machine's physical memory in bytes (8 GiB when it cannot be read).
std::uint64_t physical_memory();

}  // namespace allanlot::workflow
