#include "src/cli/cli.hpp"

#include "src/cli/analyze.hpp"
#include "src/cli/codev.hpp"
#include "src/cli/convert.hpp"
#include "src/cli/diagnose.hpp"
#include "src/cli/export.hpp"
#include "src/cli/hat.hpp"
#include "src/cli/plan.hpp"
#include "src/cli/report.hpp"
#include "src/cli/simulate.hpp"
#include "src/cli/summarize.hpp"
#include "src/cli/watch.hpp"
#include "src/workflow/input_args.hpp"
#include "src/workflow/notes.hpp"

#include <allanlot/version.hpp>

#include <CLI/CLI.hpp>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string_view>
#include <thread>
#include <vector>

namespace allanlot::cli {
namespace {

std::string join_args(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    if (i) s += ' ';
    const std::string a = argv[i];
    s += a.find_first_of(" \t'\"") == std::string::npos ? a : "'" + a + "'";
  }
  return s;
}

// OMP_NUM_THREADS beyond what the machine can run is capped, as --threads is checked
// (kernels::thread_cap, docs/cli.md "Threads"); said here once, where the user set it.
void cap_omp_threads(std::ostream& err) {
#ifdef _OPENMP
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (!env) return;
  char* end = nullptr;
  const long asked = std::strtol(env, &end, 10);  // the first level of a list "8,2"
  const long cap = kernels::thread_cap();
  if (end == env || asked <= cap) return;
  omp_set_num_threads(static_cast<int>(cap));
  err << "allanlot: note: OMP_NUM_THREADS=" << env << " is more than this machine runs; using "
      << cap << " threads\n";
#else
  (void)err;
#endif
}

int usage_error(const char* what) {
  std::cerr << "allanlot: usage error: " << what << "\n"
            << "Run 'allanlot --help' or 'allanlot <command> --help'.\n";
  return kExitUsage;
}

}  // namespace

int run(int argc, char** argv) {
  // Before the command line is parsed (the cap must precede any parallel region): -q, which
  // prints errors only, is looked for among the arguments as given.
  const bool quiet = std::any_of(argv + 1, argv + argc, [](const char* a) {
    return std::string_view(a) == "-q" || std::string_view(a) == "--quiet";
  });
  cap_omp_threads(workflow::notes_stream(quiet, std::cerr));
  CLI::App app{"allanlot: Allan-family noise characterization of sensor production lots"};
  app.set_version_flag("--version", std::string("allanlot ") + kVersion + " (" + kGitSha + ")");
  app.require_subcommand(1);

  // In the order of `allanlot --help` (and the man page).
  const std::vector<Command> commands = {
      add_analyze_command(app),  add_simulate_command(app), add_summarize_command(app),
      add_diagnose_command(app), add_report_command(app),   add_export_command(app),
      add_convert_command(app),  add_hat_command(app),      add_codev_command(app),
      add_plan_command(app),     add_watch_command(app)};

  try {
    app.parse(argc, argv);
    for (const auto& c : commands)
      if (*c.app) return c.run(join_args(argc, argv));
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kExitOk;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // CLI11's own exit codes differ per error; docs/cli.md says 2 for every usage error.
    return usage_error(e.what());
  } catch (const workflow::OptionError& e) {
    // An argument that a workflow found wrong once it looked at it (an INPUT that is a list
    // of files, not data) is a usage error as CLI11's are.
    return usage_error(e.what());
  } catch (const std::exception& e) {
    std::cerr << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  return kExitUsage;
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        return end != text.c_str() && std::isfinite(v) ? "" : "not a finite number: " + text;
      },
      "FINITE");
}

CLI::Validator seed_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 20 &&
                            std::all_of(text.begin(), text.end(),
                                        [](unsigned char c) { return std::isdigit(c) != 0; });
        // 20 digits may still exceed 2^64 - 1 = 18446744073709551615.
        const bool fits = digits && (text.size() < 20 || text <= "18446744073709551615");
        return fits ? "" : "not a whole number from 0 to 18446744073709551615: " + text;
      },
      "UINT64");
}

}  // namespace allanlot::cli
