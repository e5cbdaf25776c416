// One recording analysed (docs/cli.md "Command: analyze"): its channels read in memory-bounded
// waves across threads, each analysed by src/pipeline/channel.hpp, the poor fits modelled, and
// the results file's record of them made (not written: src/workflow/analyze.hpp writes it).
#pragma once

#include "io/results.hpp"
#include "src/workflow/analyze.hpp"

#include <cstdint>
#include <iosfwd>
#include <string>

namespace allanlot::workflow {

/// Analyses one recording. Throws io::Error when the input as a whole cannot be analysed
/// (unreadable, no channel, every channel failed); channel failures inside a readable file are
/// recorded in the channel's status, reported on `err` and set `channel_failed`. At most
/// min(threads, memory_limit / (32 bytes x samples)) channels (at least one) are in memory at
/// once, each freed as soon as it is analysed; every kernel is thread-invariant, so neither
/// number changes a result. A channel that alone exceeds the limit fails, unread.
io::RecordingResult analyze_recording(const std::string& file, const AnalyzeOptions& opt,
                                      int threads, std::uint64_t memory_limit, StageTimes& times,
                                      std::ostream& err, bool& channel_failed);

}  // namespace allanlot::workflow
