#include "src/cli/summarize.hpp"

#include "io/atomic_file.hpp"
#include "src/lot/spec.hpp"
#include "src/lot/summary.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <optional>
#include <ostream>
#include <system_error>

namespace fs = std::filesystem;

namespace allanlot::cli {

int run_summarize(const SummarizeOptions& opt, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(opt.outdir, ec)) {
    err << "allanlot: error: " << opt.outdir.string() << " is not a directory\n";
    return 2;
  }
  // A bad spec is refused, with every problem it has, before a results file is read.
  std::optional<spec::Spec> sp;
  if (!opt.spec_path.empty()) {
    try {
      sp = spec::load_spec(opt.spec_path);
    } catch (const spec::Error& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return 2;
    }
  }
  const io::DirectoryLock summary_lock(opt.outdir);
  std::size_t unreadable = 0;
  std::vector<io::SummaryRow> rows = lot::rows_from_outdir(opt.outdir, err, &unreadable);
  const std::size_t n_rows = rows.size();
  if (n_rows == 0) {
    err << "allanlot: error: " << opt.outdir.string()
        << " holds no results (*.allan.h5); no summary written\n";
    return 2;
  }
  lot::LotOverview overview;
  try {
    lot::LotOptions lot_opt;
    lot_opt.spec_path = opt.spec_path;
    lot_opt.spec = sp ? &*sp : nullptr;
    lot_opt.manifest = opt.manifest;
    lot_opt.quiet = opt.quiet;
    overview = lot::write_lot(opt.outdir, std::move(rows), lot_opt, out, err);
  } catch (const std::exception& e) {
    err << "allanlot: error: writing the lot summary: " << e.what() << "\n";
    return 2;
  }
  if (!opt.quiet)
    out << "lot summary of " << n_rows
        << " channel(s): " << (opt.outdir / "lot_summary.csv").string() << "\n";
  // Recordings of the manifest without results, and results files that cannot be read, are
  // failed inputs, as in analyze: status 1.
  return overview.n_missing > 0 || unreadable > 0 ? 1 : 0;
}

Command add_summarize_command(CLI::App& app) {
  auto opt = std::make_shared<SummarizeOptions>();
  auto dir = std::make_shared<std::string>();
  auto spec = std::make_shared<std::string>();
  auto manifest = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "summarize", "Rebuild lot_summary.h5 and lot_summary.csv from the results files present");
  sub->add_option("outdir", *dir, "Output directory of analyze")->required();
  sub->add_option("--spec", *spec, "Spec file (JSON): pass/fail limits per channel and term");
  sub->add_option("--manifest", *manifest,
                  "Manifest of the lot: recordings without a results file are listed as failed");
  sub->add_flag("-q,--quiet", opt->quiet, "Print only errors");
  return {sub, [=](const std::string&) {
            opt->outdir = *dir;
            opt->spec_path = *spec;
            opt->manifest = *manifest;
            return run_summarize(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
