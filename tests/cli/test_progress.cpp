// The progress line of `analyze` (docs/lots-and-slurm.md "Progress"): on a terminal it is
// erased before each coefficient table, so that the two never share a line; in a log there is
// none. The terminal is a pseudo-terminal from script(1) (util-linux, in every Debian).
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace allanlot
