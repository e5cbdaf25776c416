// What a workflow's caller is told when it ends: the exit statuses of the command line
// (docs/cli.md "Exit status") and the error that is the caller's fault. The command line returns
// them from main; the Python module turns a usage error into ValueError.
#pragma once

#include <exception>
#include <ostream>
#include <stdexcept>

namespace allanlot::workflow {

/// Every input analysed (or diagnosed, planned, decided pass); some inputs failed (or a limit
/// decided fail, a target not reached); usage error or nothing could be done.
enum ExitStatus : int { kExitOk = 0, kExitSomeFailed = 1, kExitUsage = 2 };

/// A request the caller must change (bad option, model, spec or channel): exit status 2 on
/// the command line, ValueError in Python, as opposed to a failure of the work itself.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Prints the exception `e` that stopped a command before any work (a spec's every message, or
/// one what()) as "allanlot: error: ..." lines on `err`, and returns kExitUsage.
int print_usage_error(const std::exception_ptr& e, std::ostream& err);

}  // namespace allanlot::workflow
