// The summarize workflow (docs/cli.md "Command: summarize"): rebuilds lot_summary.h5/.csv from
// the results files present in OUTDIR (src/lot/summary.hpp), e.g. as a Slurm merge job; analyze
// writes the same summary after its recordings (src/workflow/analyze.hpp). The command line adds
// its options.
#pragma once

#include <filesystem>
#include <iosfwd>

namespace allanlot::workflow {

struct SummarizeOptions {
  std::filesystem::path outdir;     // analyze's output directory
  std::filesystem::path spec_path;  // --spec
  std::filesystem::path manifest;   // --manifest: entries without results are listed as failed
  bool quiet = false;
};
/// Returns the exit status: 0 written; 1 written, but recordings of the manifest have no results;
/// 2 OUTDIR not a directory, no results at all, or the summary could not be written.
int run_summarize(const SummarizeOptions& opt, std::ostream& out, std::ostream& err);

}  // namespace allanlot::workflow
