// The data-editing options of `analyze` (docs/cli.md "Command: analyze", docs/editing.md):
// --drift, --outliers, --exclude and --dynamic, as given and as checked (their part of the resume
// stamp: src/workflow/analyze_stamp.hpp).
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

}  // namespace allanlot::cli
