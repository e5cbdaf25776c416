// `allanlot diagnose` (docs/diagnose.md): where a noise model disagrees with a
// measured channel, which effect is missing, and the corrected model
// (kernels/diagnose/diagnose.hpp).
#pragma once

#include "io/input_options.hpp"
#include "src/cli/cli.hpp"

#include <cstdint>
#include <iosfwd>
#include <string>

namespace allanlot::cli {

struct DiagnoseOptions {
  std::string input;               // the recording (HDF5 or text)
  std::string model_path;          // model file (JSON), required
  std::string channel;             // channel path or name; "" = the only channel
  std::string output;              // -o OUT.h5: group /<channel>/diagnosis ("" = none)
  std::string model_out;           // --model-out FILE.json: the corrected model ("" = none)
  bool json = false;               // print the JSON object of docs/diagnose.md instead
  int replicas = 30;               // Monte Carlo replicas per model
  int max_effects = 8;             // at most this many effects are added
  std::uint64_t seed = 7;          // seed of the replicas
  int threads = 0;                 // 0 = OMP_NUM_THREADS, else all cores
  io::InputOptions input_options;  // --data-type and the options of text recordings
};

/// Exit status: 0 diagnosed (whatever was found); 1 the diagnosis could not be made or written
/// (unreadable input or channel, record too short, output not writable); 2 usage error (bad
/// options, bad model file, channel missing or ambiguous, units that differ from the model's,
/// -o naming the input).
int run_diagnose(const DiagnoseOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `diagnose` subcommand to `app`.
Command add_diagnose_command(CLI::App& app);

}  // namespace allanlot::cli
