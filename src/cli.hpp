// The allanlot command line (CONTRACT "Command: ..."): parses arguments, dispatches to the
// subcommands and turns exceptions into exit statuses.
#pragma once

namespace allanlot::cli {

/// Exit statuses (CONTRACT): every input analysed; some inputs failed; usage error or
/// nothing could be analysed.
enum ExitStatus : int { kExitOk = 0, kExitSomeFailed = 1, kExitUsage = 2 };

int run(int argc, char** argv);

}  // namespace allanlot::cli
