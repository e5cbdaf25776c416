// The HTML report (`allanlot report OUTDIR [-o report.html]`, docs/reports.md): one self-contained
// HTML page (inline CSS and SVG, no scripts, nothing fetched) from the results files of `analyze`:
// a lot page (summary tables with pass/fail colouring where the lot summary has spec columns,
// per-term distributions across units, one per channel, units and data type, outliers) and, per
// unit and channel, in the coefficient table's units: OADEV with confidence intervals, the eq. (3)
// fit with its terms as slope asymptotes (the paper's Figure 1) and the other statistics behind
// tick boxes; TDEV; the PSD against the model's; the eq. (2) cross-check; the coefficient table;
// the deviation tables, folded; and, where `diagnose` has written one, the diagnosis.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::report {

enum class UnitPages {
  Auto,    // one page up to kSinglePageMaxUnits units, linked per-unit pages above
  Always,  // per-unit pages in <report stem>_units/ beside the report
  Never    // everything in one page
};

/// Lots with more units than this get per-unit pages under UnitPages::Auto: one page with
/// every curve of 500 six-channel units would be over 100 MB; the lot page alone stays at a
/// few MB and each unit page at about 650 kB (a third of it the folded deviation tables).
inline constexpr int kSinglePageMaxUnits = 20;

struct ReportOptions {
  std::filesystem::path outdir;  // analyze's output directory (results files, lot summary)
  std::filesystem::path output;  // the HTML page; "" = OUTDIR/report.html
  /// Further HDF5 files holding /<channel>/diagnosis groups (diagnose -o), matched to units
  /// by their root device_id attribute or their file name. Files in OUTDIR that are neither
  /// results files nor the lot summary are looked at too.
  std::vector<std::filesystem::path> diagnosis_files;
  UnitPages unit_pages = UnitPages::Auto;
  bool quiet = false;
  /// A spec file whose ITU-T masks ("mtie"/"tdev": {"mask": ...}) are drawn on the time-error
  /// plots of the channels its rules match; "" = none.
  std::filesystem::path spec_path;
};

/// What run_report did (the command's exit status, docs/cli.md, follows from it).
enum class Outcome {
  Written,                // every results file read, the report written
  WrittenSomeUnreadable,  // written, but some results files could not be read (named on `err`)
  UsageError  // OUTDIR not a directory or without results files, none readable, output not
              // writable, a --diagnosis file unreadable, a --spec file bad (named on `err`)
};

/// Writes the report of `opt.outdir`; prints its path on `out` unless opt.quiet.
Outcome run_report(const ReportOptions& opt, std::ostream& out, std::ostream& err);

}  // namespace allanlot::report
