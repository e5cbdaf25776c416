// The progress line of `analyze` (docs/lots-and-slurm.md "Progress"): on a terminal it is
// erased before each coefficient table, so that the two never share a line; in a log there is
// none. The terminal is a pseudo-terminal from script(1) (util-linux, in every Debian).
#include "support/h5_fixture.hpp"
#include "support/text_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

// The text a terminal shows on each line: what follows the last carriage return (the
// terminal ends each line with "\r\n", which is not one).
std::vector<std::string> shown_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.ends_with('\r')) line.pop_back();
    const std::size_t cr = line.find_last_of('\r');
    lines.push_back(cr == std::string::npos ? line : line.substr(cr + 1));
  }
  return lines;
}

TEST(Progress, OnATerminalItNeverSharesALineWithATable) {
  if (test::run_command("script -qec true /dev/null") != 0)
    GTEST_SKIP() << "script(1) cannot open a pseudo-terminal here";
  const fs::path dir = test::fresh_dir("progress_tty");
  std::string out;
  ASSERT_EQ(test::run_command(test::binary() + " simulate -q --lot 3 --duration 20 --seed 2 -o " +
                                  (dir / "lot").string(),
                              &out),
            0)
      << out;
  const std::string analyze = test::binary() + " analyze --table --stats oadev -o ";
  ASSERT_EQ(test::run_command("script -qec '" + analyze + (dir / "tty").string() + " " +
                                  (dir / "lot").string() + "' /dev/null",
                              &out),
            0)
      << out;
  EXPECT_NE(out.find("recordings, "), std::string::npos) << "no progress line:\n" << out;
  std::size_t tables = 0;
  for (const std::string& line : shown_lines(out)) {
    tables += line.find("noise coefficients") != std::string::npos ? 1 : 0;
    EXPECT_FALSE(line.find("recordings, ") != std::string::npos &&
                 line.find("noise coefficients") != std::string::npos)
        << line;
  }
  EXPECT_EQ(tables, 3u) << out;
  // In a log (no terminal): no progress line at all.
  ASSERT_EQ(
      test::run_command(analyze + (dir / "log").string() + " " + (dir / "lot").string(), &out), 0)
      << out;
  EXPECT_EQ(out.find("recordings, "), std::string::npos) << out;
}

// -q prints errors only, in every command that takes it: no note (missing samples, totdev
// skipped on gaps, a --channels glob without a match, what convert inferred), no warning (a
// spec rule that matches no channel), no table, overview or closing line. The same commands
// without -q print them, so the check can fail.
TEST(Progress, QuietPrintsNothingOnSuccess) {
  const fs::path dir = test::fresh_dir("progress_quiet");
  test::RigSpec spec;
  spec.rows = 5000;
  test::write_rig_csv(dir / "rig.csv", spec);
  const std::string rig = (dir / "rig.csv").string(), json = (dir / "spec.json").string();
  std::ofstream(json) << R"j({"channels": {"mag_*": {"B": {"max": 1, "unit": "mg"}}}})j";
  for (const bool quiet : {false, true}) {
    const std::string b = test::binary(), q = quiet ? " -q" : "";
    const fs::path base = dir / (quiet ? "quiet" : "loud");
    const std::string out = (base / "out").string();
    const std::vector<std::pair<std::string, std::string>> commands = {
        {b + " simulate" + q + " --lot 2 --duration 20 --seed 2 -o " + (base / "lot").string(),
         "wrote"},
        {b + " analyze" + q +
             " --stats oadev,totdev --no-psd --channels 'gyro_*,accel_*,mag_*,temp' --spec " +
             json + " -o " + out + " " + rig,
         "unit 'degC' (/temp) is not in allanlot's vocabulary"},
        {b + " summarize" + q + " --spec " + json + " " + out, "warning"},
        {b + " convert" + q + " -o " + (base / "conv").string() + " " + rig, "allanlot: note: "},
        {b + " report" + q + " " + out, "report"},
    };
    for (const auto& [command, said] : commands) {
      std::string text;
      ASSERT_EQ(test::run_command(command, &text), 0) << command << "\n" << text;
      if (quiet)
        EXPECT_EQ(text, "") << command;
      else
        EXPECT_NE(text.find(said), std::string::npos) << command << "\n" << text;
    }
  }
}

}  // namespace
}  // namespace allanlot
