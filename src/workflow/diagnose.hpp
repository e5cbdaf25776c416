// The diagnose workflow (docs/diagnose.md): one channel of a recording against a unit model,
// diagnosed by kernels/diagnose/diagnose.hpp, with the corrected model and the diagnosis/
// record it gives. The command line adds its options and its printed
// report; the Python module's diagnose() runs diagnose_channel on samples it is given.
#pragma once

#include "io/diagnosis.hpp"
#include "io/input_options.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "src/lot/model.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace allanlot::workflow {

/// How hard the diagnosis looks (docs/cli.md "Command: diagnose").
struct DiagnoseSettings {
  int replicas = 30;       // Monte Carlo replicas per model
  int max_effects = 8;     // at most this many effects are added
  std::uint64_t seed = 7;  // seed of the replicas
  int threads = 0;         // 0 = OMP_NUM_THREADS, else all cores
};

/// Phase samples to rate, in place: successive differences times the sample rate, one sample
/// fewer (a NaN point makes both of its increments missing, as kernels::phase_from_phase treats
/// it).
template <class Samples>
void phase_to_rate(Samples& y, double rate_hz) {
  for (std::size_t k = 0; k + 1 < y.size(); ++k)
    y[k] = (y[k + 1] - y[k]) * rate_hz;
  if (!y.empty()) y.pop_back();
}

/// One channel diagnosed: the diagnosis and the unit's model before and after (the channel's
/// effects and coefficients replaced by the diagnosis's).
struct ChannelDiagnosis {
  std::string channel;  // the name the JSON object and the record carry
  std::size_t model_channel = 0;
  kernels::Diagnosis diagnosis;
  model::UnitModel given, corrected;
};

/// Diagnoses the rate samples of one channel at `rate_hz` against channel `model_channel` of
/// `given`. Throws std::invalid_argument for the kernel's preconditions.
ChannelDiagnosis diagnose_channel(std::span<const double> rate, double rate_hz,
                                  const model::UnitModel& given, std::size_t model_channel,
                                  const std::string& channel, const DiagnoseSettings& settings);

/// `allanlot diagnose INPUT --model MODEL`: which channel of which recording, and what to write.
struct DiagnoseRequest {
  std::string input;               // the recording (HDF5 or text)
  std::string model_path;          // model file (JSON)
  std::string channel;             // channel path or name; "" = the only channel
  std::string output;              // group /<channel>/diagnosis in this HDF5 file ("" = none)
  std::string model_out;           // the corrected model file ("" = none)
  io::InputOptions input_options;  // --data-type and the options of text recordings
  DiagnoseSettings settings;
};

/// Reads the request's channel and diagnoses it against the model file; `note` receives what
/// the caller should be told but is no error (the model's sample rate differs from the
/// recording's). Throws UsageError (src/workflow/status.hpp: an output naming an input, a bad
/// model file, a channel missing or ambiguous, units that differ from the model's), io::Error
/// (the recording cannot be read) and std::exception (the diagnosis cannot be made).
ChannelDiagnosis diagnose_recording(const DiagnoseRequest& request,
                                    const std::function<void(const std::string&)>& note);

/// Writes what the request asks for: the corrected model (atomically) and the diagnosis/ group
/// (io::write_diagnosis). Throws io::Error when a file cannot be written.
void write_diagnosis_outputs(const DiagnoseRequest& request, const ChannelDiagnosis& d);

/// The diagnosis/ group's record (io/diagnosis.hpp) of `d`, read from `source_file`.
io::DiagnosisRecord diagnosis_record(const ChannelDiagnosis& d, const std::string& source_file);

}  // namespace allanlot::workflow
