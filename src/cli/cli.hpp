// The allanlot command line (docs/cli.md): parses arguments, dispatches to the
// subcommands and turns exceptions into exit statuses.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace allanlot::cli {

/// Exit statuses (docs/cli.md "Exit status"): every input analysed; some inputs failed; usage
/// error or nothing could be analysed.
enum ExitStatus : int { kExitOk = 0, kExitSomeFailed = 1, kExitUsage = 2 };

int run(int argc, char** argv);

/// A command defined in its own file: `add_<name>_command(app)` adds its subcommand and
/// options to `app` and returns the subcommand and the function that runs it once the
/// command line is parsed (returning the exit status). `run` dispatches to whichever parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

}  // namespace allanlot::cli
