// The data-editing options of `analyze` (docs/cli.md "Command: analyze", docs/editing.md):
// --drift, --outliers, --exclude and --dynamic, as given and as checked, and their part of the
// resume stamp.
#pragma once

#include "src/pipeline/channel_edits.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace allanlot::cli {

/// The options as given on the command line.
struct EditArgs {
  std::string drift = "none";
  std::string outliers = "off";
  std::vector<std::string> exclude;
  std::string dynamic;
};

/// Adds --drift, --outliers, --exclude and --dynamic to `sub`.
void add_edit_options(CLI::App* sub, EditArgs& args);

/// The options checked; throws CLI::ValidationError (a usage error) naming the option.
pipeline::EditOptions checked_edit_options(const EditArgs& args);

/// The options in the resume stamp, "" when none is given (a default run's stamp is unchanged).
std::string edit_stamp(const pipeline::EditOptions& opt);

}  // namespace allanlot::cli
