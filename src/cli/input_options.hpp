// The options that say what input recordings cannot (docs/cli.md "Input options"): --data-type
// for every recording, and what a text recording needs (--sample-rate or --tau0, --column,
// --time-column, --time-unit, --units). Shared by analyze, diagnose and convert. And the
// channel selection of analyze and export (docs/cli.md "Channel selection").
#pragma once

#include "io/input_options.hpp"
#include "src/workflow/input_args.hpp"
#include "src/workflow/inputs.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace allanlot::cli {

/// The options as given, before they are checked (src/workflow/input_args.hpp).
using workflow::InputArgs;

/// Adds the input options to `sub`, filling `args` when parsed.
void add_input_options(CLI::App* sub, InputArgs& args);

/// The checked options; throws CLI::ValidationError naming the option that is wrong.
io::InputOptions input_options(const InputArgs& args);

/// Adds --channels GLOB,... and --exclude-channels GLOB,... (each repeatable) to `sub`.
void add_channel_options(CLI::App* sub, std::vector<std::string>& include,
                         std::vector<std::string>& exclude);

/// The selection they say; throws CLI::ValidationError naming --channels when a glob is empty.
workflow::ChannelSelection channel_selection(const std::vector<std::string>& include,
                                             const std::vector<std::string>& exclude);

/// Throws CLI::ValidationError (a usage error, exit 2) when a text recording among `files`
/// needs an option that was not given, naming the file and the option. HDF5 files pass.
void check_inputs_need(const std::vector<std::string>& files, const io::InputOptions& options);

}  // namespace allanlot::cli
