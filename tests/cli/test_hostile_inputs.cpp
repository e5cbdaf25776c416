// Hostile inputs and outputs through the real binary: a gzip bomb fails its file at
// --memory-limit and the lot goes on; a FIFO at OUTDIR/report.html is an error, not a wait;
// units named in other scripts keep results files of their own.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sys/stat.h>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

// A CSV of `n` rows at 100 Hz: a time column and two noise channels.
void write_csv(const fs::path& path, std::size_t n, unsigned seed) {
  const std::vector<double> a = test::noise(n, seed), b = test::noise(n, seed + 1);
  std::ofstream f(path);
  f << "time [s],gx [deg/s],gy [deg/s]\n";
  for (std::size_t i = 0; i < n; ++i)
    f << static_cast<double>(i) / 100.0 << "," << a[i] << "," << b[i] << "\n";
}

// `analyze` of dir/in into dir/out (quick options), its status; its output in `text`.
int analyze(const fs::path& dir, std::string& text, const std::string& options = "") {
  return run_command(binary() + " analyze -q --taus octave --no-psd " + options + " -o " +
                         (dir / "out").string() + " " + (dir / "in").string(),
                     &text);
}

std::string read_file(const fs::path& p) {
  std::ifstream f(p);
  return {std::istreambuf_iterator<char>(f), {}};
}

// 1 MB of gzip that decode to 256 MiB of rows: with --memory-limit 8M the bomb fails by name at
// the limit (a few MiB decoded, never the whole), the good unit is analysed.
TEST(HostileInputs, AGzipBombFailsAtTheMemoryLimitAndTheLotGoesOn) {
  const fs::path dir = test::fresh_dir("hostile_bomb");
  fs::create_directories(dir / "in");
  write_csv(dir / "in" / "good.csv", 2000, 3);
  const fs::path bomb = dir / "in" / "bomb.csv.gz";
  ASSERT_EQ(std::system(("(echo 'time,gx,gy'; yes 0,1,2) | head -c 268435456 | gzip -1 > '" +
                         bomb.string() + "'")
                            .c_str()),
            0);
  ASSERT_LT(fs::file_size(bomb), std::uintmax_t{4} << 20);
  std::string text;
  EXPECT_EQ(analyze(dir, text, "--memory-limit 8M"), 1) << text;
  EXPECT_NE(text.find("allanlot: error: " + bomb.string() + ":line "), std::string::npos) << text;
  EXPECT_NE(text.find("its values need more than the memory limit of 8.0 MiB (--memory-limit)"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("bad_alloc"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(dir / "out" / "good.allan.h5"));
  EXPECT_FALSE(fs::exists(dir / "out" / "bomb.allan.h5"));
  const std::string summary = read_file(dir / "out" / "lot_summary.csv");
  // Named as its results would be (`bomb`, not `bomb.csv`), with the line in the channel cell.
  EXPECT_NE(summary.find("\nbomb,line "), std::string::npos) << summary;
  EXPECT_NE(summary.find(",\"failed: its values need more than the memory limit of 8.0 MiB"),
            std::string::npos)
      << summary;
}

// A named pipe where report.html goes is an error naming it, never a wait for a reader.
TEST(HostileInputs, AFifoAtTheReportIsAnErrorNotAWait) {
  const fs::path dir = test::fresh_dir("hostile_report_fifo");
  fs::create_directories(dir / "in");
  write_csv(dir / "in" / "u1.csv", 2000, 5);
  std::string text;
  ASSERT_EQ(analyze(dir, text), 0) << text;
  const fs::path fifo = dir / "out" / "report.html";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // `timeout` ends a hang with 124: the test fails instead of blocking CTest.
  const int status =
      run_command("timeout 120 " + binary() + " report " + (dir / "out").string(), &text);
  EXPECT_EQ(status, 2) << text;  // nothing could be written
  EXPECT_NE(text.find(fifo.string()), std::string::npos) << text;
  EXPECT_NE(text.find("named pipe that nobody reads"), std::string::npos) << text;
  EXPECT_TRUE(fs::is_fifo(fifo));
}

// Two units named in Cyrillic and one in CJK: three results files, none refused as sharing a
// device_id (each once reduced to a run of '_').
TEST(HostileInputs, UnitsNamedInOtherScriptsKeepTheirOwnResults) {
  const fs::path dir = test::fresh_dir("hostile_scripts");
  fs::create_directories(dir / "in");
  const std::vector<std::string> names = {"датчик", "гироскоп", "陀螺仪"};
  for (std::size_t i = 0; i < names.size(); ++i)
    write_csv(dir / "in" / (names[i] + ".csv"), 2000, 10 + static_cast<unsigned>(i));
  std::string text;
  EXPECT_EQ(analyze(dir, text), 0) << text;
  for (const std::string& name : names) {
    const fs::path results = dir / "out" / (name + ".allan.h5");
    ASSERT_TRUE(fs::exists(results)) << name << "\n" << text;
    EXPECT_EQ(io::read_results(results).device_id, name);
  }
}

// Units whose names are spreadsheet formulas (their device_ids, from the file names): every
// cell of lot_summary.csv and of the CSV export that would start a formula starts with a quote.
TEST(HostileInputs, FormulaDeviceIdsAreTextInEveryCsv) {
  const fs::path dir = test::fresh_dir("hostile_formula");
  fs::create_directories(dir / "in");
  write_csv(dir / "in" / "=SUM(1+1).csv", 2000, 20);
  write_csv(dir / "in" / "@cmd.csv", 2000, 21);
  std::string text;
  ASSERT_EQ(analyze(dir, text), 0) << text;
  ASSERT_EQ(run_command(binary() + " export " + (dir / "out").string() + " -o " +
                            (dir / "export.csv").string(),
                        &text),
            0)
      << text;
  for (const fs::path& csv : {dir / "out" / "lot_summary.csv", dir / "export.csv"}) {
    std::ifstream in(csv);
    int rows = 0;
    for (std::string line; std::getline(in, line);) {
      if (line.find("SUM(1+1)") == std::string::npos && line.find("@cmd") == std::string::npos)
        continue;
      ++rows;
      EXPECT_TRUE(line.starts_with("\"'=SUM(1+1)\",") || line.starts_with("\"'@cmd\","))
          << csv << ": " << line;
    }
    EXPECT_GE(rows, 4) << csv;  // two channels of each unit
  }
}

}  // namespace
}  // namespace allanlot
