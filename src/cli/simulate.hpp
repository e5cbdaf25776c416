// `allanlot simulate` (docs/cli.md "Command: simulate"): recordings from a noise model, one unit
// or a whole lot.
#pragma once

#include "src/cli/cli.hpp"

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>

namespace allanlot::cli {

struct SimulateOptions {
  std::string model_path;          // "" = the embedded demo unit (the paper's Table)
  double duration_s = 5400.0;      // record length; 90 minutes, the paper's
  std::uint64_t seed = 1;          // same seed and model: the same bytes
  std::string channel = "gyro_x";  // dataset name of a single-channel model
  int lot = 0;                     // > 0: write that many units into a directory
  std::filesystem::path output;    // FILE.h5, or DIR with --lot
  int threads = 0;                 // 0 = OMP_NUM_THREADS, else all cores
  bool quiet = false;
};

/// Returns the exit status: 0 written, 2 usage error (bad model, bad options, unwritable
/// output). Nothing is left under an output name unless it is complete.
int run_simulate(const SimulateOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `simulate` subcommand to `app` (see cli.hpp, struct Command).
Command add_simulate_command(CLI::App& app);

}  // namespace allanlot::cli
