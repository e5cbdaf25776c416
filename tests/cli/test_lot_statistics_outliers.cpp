// One outlier list everywhere (src/lot/statistics.hpp, compute_lot_statistics): on a simulated
// lot with two units far off, the lot summary (lot_summary.h5 and .csv, lot_statistics.csv),
// the terminal overview of analyze and of summarize, and the report's outlier table name the
// same units, channels, terms and z.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

// (device, channel, term, z as printed)
using Flag = std::tuple<std::string, std::string, std::string, std::string>;

// The flags of the lot summary's rows: outlier_terms "N z=+26; B z=-4.1".
std::set<Flag> summary_flags(const std::vector<io::SummaryRow>& rows) {
  std::set<Flag> out;
  const std::regex term(R"(([RKBNQ]) z=([-+][0-9.e+-]+))");
  for (const auto& r : rows) {
    if (!r.outlier) continue;
    for (std::sregex_iterator it(r.outlier_terms.begin(), r.outlier_terms.end(), term), end;
         it != end; ++it)
      out.insert({r.device_id, r.channel, (*it)[1], (*it)[2]});
  }
  return out;
}

// The terminal overview's line "outliers (2): dev:/chan (N z=+26); dev:/chan (N z=+25; B ...)".
std::set<Flag> terminal_flags(const std::string& out) {
  std::set<Flag> flags;
  const auto at = out.find("outliers (");
  if (at == std::string::npos) return flags;
  const std::string line = out.substr(at, out.find('\n', at) - at);
  const std::regex unit(R"(([A-Za-z0-9_.-]+):(/[^ ]+) \(([^)]*)\))");
  const std::regex term(R"(([RKBNQ]) z=([-+][0-9.e+-]+))");
  for (std::sregex_iterator it(line.begin(), line.end(), unit), end; it != end; ++it) {
    const std::string terms = (*it)[3];
    for (std::sregex_iterator t(terms.begin(), terms.end(), term); t != end; ++t)
      flags.insert({(*it)[1], (*it)[2], (*t)[1], (*t)[2]});
  }
  return flags;
}

// The report's "Outlier units" table: unit, channel, term, value, unit, ratio, z.
std::set<Flag> report_flags(const std::string& html) {
  std::set<Flag> flags;
  const auto begin = html.find("<h2>Outlier units</h2>");
  if (begin == std::string::npos) return flags;
  const auto end = html.find("</table>", begin);
  const std::string table = html.substr(begin, end - begin);
  const std::regex row(
      R"(<tr><td class="l"><a href="[^"]*">([^<]+)</a></td><td class="l">([^<]+)</td><td>)"
      R"(([RKBNQ])</td><td>[^<]*</td><td class="l">[^<]*</td><td>[^<]*</td><td>([^<]+)</td></tr>)");
  for (std::sregex_iterator it(table.begin(), table.end(), row), e; it != e; ++it)
    flags.insert({(*it)[1], (*it)[2], (*it)[3], (*it)[4]});
  return flags;
}

TEST(LotOutliers, SummaryTerminalAndReportListTheSameOutliers) {
  const auto dir = test::fresh_dir("lot_outliers");
  // Six ordinary units (N scattered by 3 % across the lot) and two made with N five and six
  // times larger: far outside the lot's spread and their own uncertainty.
  const auto model = [](double n_scale) {
    std::ostringstream m;
    m << R"j({"sample_rate_hz": 100, "channels": {
          "gyro_x": {"units": "deg/s", "terms": {"N": )j"
      << 0.005 * n_scale << R"j(, "B": 0.00125}},
          "accel_x": {"units": "m/s^2", "terms": {"N": 0.0005}}},
        "lot_spread": {"N": 0.03}})j";
    return m.str();
  };
  {
    std::ofstream(dir / "model.json") << model(1);
    std::ofstream(dir / "odd5.json") << model(5);
    std::ofstream(dir / "odd6.json") << model(6);
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " simulate -q --model " + (dir / "model.json").string() +
                            " --lot 6 --duration 120 --seed 11 -o " + (dir / "lot").string(),
                        &out),
            0)
      << out;
  for (const char* odd : {"odd5", "odd6"})
    ASSERT_EQ(run_command(binary() + " simulate -q --model " +
                              (dir / (std::string(odd) + ".json")).string() +
                              " --duration 120 --seed 12 -o " +
                              (dir / "lot" / (std::string(odd) + ".h5")).string(),
                          &out),
              0)
        << out;
  {
    std::ofstream m(dir / "lot" / "manifest.txt", std::ios::app);
    m << "odd5.h5\nodd6.h5\n";
  }
  std::string analyze_out;
  ASSERT_EQ(run_command(binary() + " analyze --stats oadev --threads 2 --no-psd -o " +
                            (dir / "out").string() + " @" + (dir / "lot" / "manifest.txt").string(),
                        &analyze_out),
            0)
      << analyze_out;

  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 16u);
  const std::set<Flag> summary = summary_flags(rows);
  // The planted ones are there: both odd units on N of their gyro.
  std::set<std::string> n_gyro;
  for (const auto& [device, channel, term, z] : summary)
    if (term == "N" && channel.ends_with("gyro_x")) n_gyro.insert(device);
  EXPECT_EQ(n_gyro, (std::set<std::string>{"odd5", "odd6"})) << analyze_out;
  // lot_statistics counts each flag once.
  std::size_t counted = 0;
  for (const auto& s : io::read_lot_statistics(dir / "out" / "lot_summary.h5"))
    counted += static_cast<std::size_t>(s.n_outliers);
  EXPECT_EQ(counted, summary.size());
  // The CSV holds the same column as the HDF5 file.
  const std::string csv = test::file_bytes(dir / "out" / "lot_summary.csv");
  for (const auto& r : rows) {
    if (r.outlier) {
      EXPECT_NE(csv.find(r.outlier_terms), std::string::npos) << r.outlier_terms;
    }
  }

  // The terminal, after analyze and after summarize.
  EXPECT_EQ(terminal_flags(analyze_out), summary) << analyze_out;
  std::string summarize_out;
  ASSERT_EQ(run_command(binary() + " summarize " + (dir / "out").string(), &summarize_out), 0)
      << summarize_out;
  EXPECT_EQ(terminal_flags(summarize_out), summary) << summarize_out;

  // The report.
  ASSERT_EQ(run_command(binary() + " report " + (dir / "out").string(), &out), 0) << out;
  EXPECT_EQ(report_flags(test::file_bytes(dir / "out" / "report.html")), summary);
}

}  // namespace
}  // namespace allanlot
