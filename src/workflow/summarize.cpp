#include "src/workflow/summarize.hpp"

#include "io/atomic_file.hpp"
#include "src/lot/spec.hpp"
#include "src/lot/summary.hpp"
#include "src/workflow/status.hpp"

#include <optional>
#include <ostream>
#include <system_error>

namespace fs = std::filesystem;

namespace allanlot::workflow {

int run_summarize(const SummarizeOptions& opt, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(opt.outdir, ec)) {
    err << "allanlot: error: " << opt.outdir.string() << " is not a directory\n";
    return kExitUsage;
  }
  // A bad spec is refused, with every problem it has, before a results file is read.
  std::optional<spec::Spec> sp;
  if (!opt.spec_path.empty()) {
    try {
      sp = spec::load_spec(opt.spec_path);
    } catch (const spec::Error& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return kExitUsage;
    }
  }
  const io::DirectoryLock summary_lock(opt.outdir);
  std::size_t unreadable = 0;
  std::vector<io::SummaryRow> rows = lot::rows_from_outdir(opt.outdir, err, &unreadable);
  const std::size_t n_rows = rows.size();
  if (n_rows == 0) {
    err << "allanlot: error: " << opt.outdir.string()
        << " holds no results (*.allan.h5); no summary written\n";
    return kExitUsage;
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
    return kExitUsage;
  }
  if (!opt.quiet)
    out << "lot summary of " << n_rows
        << " channel(s): " << (opt.outdir / "lot_summary.csv").string() << "\n";
  // Recordings of the manifest without results, and results files that cannot be read, are
  // failed inputs, as in analyze: status 1.
  return overview.n_missing > 0 || unreadable > 0 ? kExitSomeFailed : kExitOk;
}

}  // namespace allanlot::workflow
