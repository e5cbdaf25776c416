#include "src/cli/report.hpp"

#include "src/report/report.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace allanlot::cli {

Command add_report_command(CLI::App& app) {
  auto opt = std::make_shared<report::ReportOptions>();
  auto pages = std::make_shared<std::string>("auto");
  auto outdir = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto diag = std::make_shared<std::vector<std::string>>();
  auto* sub = app.add_subcommand(
      "report", "Write a self-contained HTML report (plots, tables) of analyze's results");
  sub->add_option("outdir", *outdir, "Output directory of analyze")->required();
  sub->add_option("-o,--output", *output, "HTML file to write (default: OUTDIR/report.html)");
  sub->add_option("--diagnosis", *diag,
                  "HDF5 files written by 'diagnose -o' to include (matched by device_id)");
  sub->add_option("--unit-pages", *pages,
                  "Per-unit pages beside the report: auto (above " +
                      std::to_string(report::kSinglePageMaxUnits) + " units), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  sub->add_flag("-q,--quiet", opt->quiet, "Print only errors");
  auto spec = std::make_shared<std::string>();
  sub->add_option("--spec", *spec,
                  "Spec file whose ITU-T masks (mtie, tdev) are drawn on the time-error plots");
  return {sub, [=](const std::string&) {
            opt->outdir = *outdir;
            opt->spec_path = *spec;
            opt->output = *output;
            opt->diagnosis_files.assign(diag->begin(), diag->end());
            opt->unit_pages = *pages == "always"  ? report::UnitPages::Always
                              : *pages == "never" ? report::UnitPages::Never
                                                  : report::UnitPages::Auto;
            switch (report::run_report(*opt, std::cout, std::cerr)) {
            case report::Outcome::Written:
              return kExitOk;
            case report::Outcome::WrittenSomeUnreadable:
              return kExitSomeFailed;
            case report::Outcome::UsageError:
              break;
            }
            return kExitUsage;
          }};
}

}  // namespace allanlot::cli
