// Which results file in OUTDIR belongs to which recording (docs/lots-and-slurm.md "Running a lot",
// Resume): resume skips a recording whose complete, current results are present, and a recording
// never replaces the results of another recording that happens to have the same device_id, neither
// in a later run nor in a concurrent one (two Slurm shards).
#pragma once

#include "io/fingerprint.hpp"
#include "src/workflow/analyze.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>

namespace allanlot::workflow {

/// The results file of `file` in OUTDIR when it is complete and current (see
/// io/fingerprint.hpp), with the device id it was found under; nullopt otherwise (absent,
/// damaged, other options, input changed, or the input cannot be opened: then analyze reports
/// the input's own error).
std::optional<std::pair<std::filesystem::path, std::string>>
current_results(const std::string& file, const io::InputStat& st, const std::string& options,
                const AnalyzeOptions& opt);

/// Empty when the results of `file` (content hash `input_hash`) may be written to `results`;
/// otherwise why not: `results` holds the intact results of another recording (another
/// source file whose samples differ). A damaged or unsealed file there is replaced.
std::string results_of_another_recording(const std::filesystem::path& results,
                                         const std::string& file, const std::string& input_hash);

}  // namespace allanlot::workflow
