#include "src/cli/cli.hpp"

#include "src/cli/analyze.hpp"
#include "src/cli/diagnose.hpp"
#include "src/cli/export.hpp"
#include "src/cli/report.hpp"
#include "src/cli/simulate.hpp"
#include "src/cli/summarize.hpp"

#include <allanlot/version.hpp>

#include <CLI/CLI.hpp>

#include <iostream>
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

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"allanlot: Allan-family noise characterization of sensor production lots"};
  app.set_version_flag("--version", std::string("allanlot ") + kVersion + " (" + kGitSha + ")");
  app.require_subcommand(1);

  // In the order of `allanlot --help` (and the man page).
  const std::vector<Command> commands = {add_analyze_command(app),   add_simulate_command(app),
                                         add_summarize_command(app), add_diagnose_command(app),
                                         add_report_command(app),    add_export_command(app)};

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
    std::cerr << "allanlot: usage error: " << e.what() << "\n"
              << "Run 'allanlot --help' or 'allanlot <command> --help'.\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  return kExitUsage;
}

}  // namespace allanlot::cli
