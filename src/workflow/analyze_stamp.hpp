// The resume stamp of `analyze` (io/fingerprint.hpp): the options that change what a results
// file holds, canonically written, so that a results file is current exactly when a rerun
// with the same options would write the same numbers.
#pragma once

#include "src/workflow/analyze.hpp"

#include <string>
#include <vector>

namespace allanlot::workflow {

/// The statistics' names, comma-separated, in the order given.
std::string join_stats(const std::vector<kernels::Stat>& stats);

/// The data-editing options (--drift, --outliers, --exclude, --dynamic), "" when none is given
/// (a default run's stamp is unchanged).
std::string edit_stamp(const pipeline::EditOptions& opt);

/// The options that change what a results file holds; the thread count and the output switches
/// that do not change numbers (--table, --verbose, --quiet, --no-summary, --memory-limit) are
/// not in it, and the options added since the first version only when they are not their
/// default, so that results files written by default runs stay current.
std::string options_stamp(const AnalyzeOptions& opt);

}  // namespace allanlot::workflow
