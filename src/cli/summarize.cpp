#include "src/cli/summarize.hpp"

#include "src/workflow/summarize.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <string>

namespace allanlot::cli {

Command add_summarize_command(CLI::App& app) {
  auto opt = std::make_shared<workflow::SummarizeOptions>();
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
            return workflow::run_summarize(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
