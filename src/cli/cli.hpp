// The allanlot command line (docs/cli.md): parses arguments, dispatches to the
// subcommands and turns exceptions into exit statuses.
#pragma once

#include "kernels/common/thread_cap.hpp"
#include "src/workflow/status.hpp"

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace allanlot::cli {

/// Exit statuses (docs/cli.md "Exit status"): every input analysed; some inputs failed; usage
/// error or nothing could be analysed. The workflows under the commands own them.
using workflow::ExitStatus;
using enum workflow::ExitStatus;

int run(int argc, char** argv);

/// Every command is defined in its own file, src/cli/<name>.cpp: `add_<name>_command(app)`
/// adds its subcommand and options to `app` and returns the subcommand and the function that
/// runs it once the command line is parsed, given the whole command line as typed (analyze
/// records it in every results file), and returns the exit status. `run` adds every command
/// from one list and dispatches to whichever was parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int(const std::string& command_line)> run;
};

/// The largest --threads any command accepts (kernels/common/parallel.hpp owns it).
inline constexpr int kMaxThreads = kernels::kMaxThreads;

/// Validators the commands share, for what CLI11 lets through: a number that is neither NaN
/// nor infinite (CLI::Range passes NaN), and a seed that is a whole number from 0 to 2^64 - 1
/// (CLI11 turns "-1" into 2^64 - 1 and "1e23" into 2^64 - 1 without a word).
CLI::Validator finite_number();
CLI::Validator seed_number();

}  // namespace allanlot::cli
