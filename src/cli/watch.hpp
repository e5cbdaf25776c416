// `allanlot watch` (docs/cli.md "Command: watch", docs/production.md): the options of the watch
// workflow (src/workflow/watch.hpp).
#pragma once

#include "src/cli/cli.hpp"

namespace allanlot::cli {

/// Adds the `watch` subcommand to `app` (see cli.hpp, struct Command).
Command add_watch_command(CLI::App& app);

}  // namespace allanlot::cli
