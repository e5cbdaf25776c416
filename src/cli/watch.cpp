#include "src/cli/watch.hpp"

#include "src/cli/input_options.hpp"
#include "src/workflow/watch.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

namespace allanlot::cli {

Command add_watch_command(CLI::App& app) {
  auto opt = std::make_shared<workflow::WatchOptions>();
  auto* sub = app.add_subcommand("watch", "Follow a growing recording and decide its spec as "
                                          "soon as the data allow (sequential looks)");
  sub->add_option("RECORDING", opt->recording, "Recording being written (HDF5 or text)")
      ->required();
  sub->add_option("--spec", opt->spec_path, "Spec file (limits to decide)")->required();
  sub->add_option("--interval", opt->interval_s, "Seconds of recording between looks")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub->add_option("--max-duration", opt->max_duration_s, "Longest recording watched, seconds")
      ->check(CLI::PositiveNumber)
      ->required();
  sub->add_option("--poll", opt->poll_s, "Wall seconds between checks for new data")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_option("--idle-timeout", opt->idle_timeout_s,
                  "Wall seconds without new data before giving up")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_flag("--replay", opt->replay,
                "The recording is complete: judge it as it grew, without waiting");
  sub->add_option("--confidence", opt->confidence, "Confidence (default: the spec's)")
      ->check(CLI::Range(1e-6, 1.0 - 1e-9));
  sub->add_option("--threads", opt->threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  add_input_options(sub, opt->input);
  return {sub,
          [opt](const std::string&) { return workflow::run_watch(*opt, std::cout, std::cerr); }};
}

}  // namespace allanlot::cli
