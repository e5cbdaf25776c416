// `allanlot summarize OUTDIR` (docs/cli.md "Command: summarize"): rebuilds lot_summary.h5/.csv
// from the results files present (src/lot/summary.hpp), e.g. as a Slurm merge job.
#pragma once

#include "src/cli/cli.hpp"

#include <filesystem>
#include <iosfwd>

namespace allanlot::cli {

struct SummarizeOptions {
  std::filesystem::path outdir;     // analyze's output directory
  std::filesystem::path spec_path;  // --spec
  std::filesystem::path manifest;   // --manifest: entries without results are listed as failed
  bool quiet = false;
};
/// Returns the exit status: 0 written; 1 written, but recordings of the manifest have no results;
/// 2 OUTDIR not a directory, no results at all, or the summary could not be written.
int run_summarize(const SummarizeOptions& opt, std::ostream& out, std::ostream& err);

/// Adds the `summarize` subcommand to `app` (see cli.hpp, struct Command).
Command add_summarize_command(CLI::App& app);

}  // namespace allanlot::cli
