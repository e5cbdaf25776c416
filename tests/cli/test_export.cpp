// `allanlot export`: Stable32 tables compared row by row with Stable32's own output for
// PHASE.DAT (AF, Tau, # and Alpha exact, Sigma to the printed digits, the bounds to 1 %), the
// tidy CSV's shape, and the errors.
#include "src/cli/export.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

const fs::path kStable32 = fs::path(ALLANLOT_REFERENCE_DIR) / "stable32" / "phasedat";

std::vector<double> read_numbers(const fs::path& p) {
  std::ifstream in(p);
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') v.push_back(std::stod(line));
  return v;
}

// Data rows (not '#') of a Stable32-format table, split into whitespace-separated fields.
std::vector<std::vector<std::string>> table_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<std::string> f;
    for (std::string w; ls >> w;)
      f.push_back(w);
    rows.push_back(f);
  }
  return rows;
}

TEST(Export, Stable32BlockHasStable32sColumnsAndNumberFormat) {
  kernels::StatResult s;
  s.m = {1, 128};
  s.tau_s = {1.0, 128.0};
  s.n = {999, 745};
  s.dev = {2.9223e-01, 2.7674e-02};
  s.dev_lo = {2.8515e-01, 2.3045e-02};
  s.dev_hi = {2.9987e-01, 3.7027e-02};
  s.edf = {900, 20};
  s.alpha = {0, 0};
  s.confidence = 0.683;
  const std::string b = cli::stable32_block("dev", "/phase", "s", "oadev", s);
  // Rows exactly as Stable32 1.60 prints them (phase_dat_oadev_octave.txt).
  EXPECT_NE(b.find("\n    1   1.0000e+00      999     0   2.8515e-01    2.9223e-01     "
                   "2.9987e-01\n"),
            std::string::npos)
      << b;
  EXPECT_NE(b.find("\n  128   1.2800e+02      745     0   2.3045e-02    2.7674e-02     "
                   "3.7027e-02\n"),
            std::string::npos)
      << b;
  EXPECT_NE(b.find("# Sigma Type: Overlapping Allan\n"), std::string::npos);
  EXPECT_NE(b.find("# Confidence Factor = 0.683\n"), std::string::npos);
  EXPECT_NE(b.find("#  AF        Tau        #    Alpha  Min Sigma      Sigma         Max Sigma\n"),
            std::string::npos);
  // Without intervals the bounds are printed as 0, as Stable32 does.
  s.confidence = 0;
  const auto rows = table_rows(cli::stable32_block("dev", "/phase", "s", "adev", s));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][4], "0.0000e+00");
  EXPECT_EQ(rows[0][6], "0.0000e+00");
}

// PHASE.DAT through the whole program: recording -> analyze -> export, against Stable32.
TEST(Export, Stable32TablesMatchStable32OnPhaseDat) {
  const fs::path d = test::fresh_dir("export_phasedat");
  {
    test::H5Fixture f(d / "phasedat.h5");
    f.dataset("/clock/x", read_numbers(kStable32 / "PHASE.DAT"), H5T_IEEE_F64LE);
    f.attr("/clock/x", "sample_rate_hz", 1.0);
    f.attr("/clock/x", "data_type", std::string("phase"));
    f.attr("/clock/x", "units", std::string("s"));
  }
  std::string out;
  ASSERT_EQ(run_command(binary() +
                            " analyze -q --no-fit --no-psd --stats oadev,mdev,ohdev "
                            "--taus octave -o " +
                            (d / "res").string() + " " + (d / "phasedat.h5").string(),
                        &out),
            0)
      << out;
  for (const char* stat : {"oadev", "mdev", "ohdev"}) {
    const fs::path table = d / (std::string(stat) + ".txt");
    ASSERT_EQ(run_command(binary() + " export " + (d / "res").string() +
                              " --format stable32 --stats " + stat + " -o " + table.string(),
                          &out),
              0)
        << out;
    const auto ours = table_rows(test::file_bytes(table));
    const auto ref = table_rows(
        test::file_bytes(kStable32 / ("phase_dat_" + std::string(stat) + "_octave.txt")));
    ASSERT_EQ(ours.size(), ref.size()) << stat;
    for (std::size_t i = 0; i < ref.size(); ++i) {
      ASSERT_EQ(ours[i].size(), 7u);
      for (std::size_t c : {0u, 1u, 2u, 3u})  // AF, Tau, #, Alpha: exactly as printed
        EXPECT_EQ(ours[i][c], ref[i][c]) << stat << " row " << i << " column " << c;
      // Sigma: both rounded to 5 digits; at most one unit of the last digit apart.
      EXPECT_NEAR(std::stod(ours[i][5]), std::stod(ref[i][5]), 1.01e-4 * std::stod(ref[i][5]))
          << stat << " row " << i;
      for (std::size_t c : {4u, 6u})  // the confidence bounds (tests/kernels/test_confidence)
        EXPECT_NEAR(std::stod(ours[i][c]), std::stod(ref[i][c]), 0.01 * std::stod(ref[i][c]))
            << stat << " row " << i << " column " << c;
    }
  }

  // Tidy CSV: one header, one row per tau of each statistic, the same numbers.
  ASSERT_EQ(run_command(binary() + " export --format csv " +
                        (d / "res" / "phasedat.allan.h5").string() + " > " +
                        (d / "all.csv").string()),
            0);
  std::istringstream csv(test::file_bytes(d / "all.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "device_id,channel,units,stat,m,tau,n,alpha,dev_lo,dev,dev_hi,edf,confidence");
  std::size_t rows = 0;
  bool found = false;
  while (std::getline(csv, line)) {
    ++rows;
    if (line.rfind("phasedat,/clock/x,s,oadev,1,1,999,0,", 0) == 0) {
      found = true;
      EXPECT_NEAR(std::stod(line.substr(line.find(",0,") + 3)), 2.8515e-01, 3e-3) << line;
    }
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(rows, 3u * 8u);  // octave m = 1 .. 128 for N = 1001 (m <= 250), each statistic

  // One unreadable file among readable ones: the others are exported, exit status 1.
  {
    std::ofstream bad(d / "res" / "zz_broken.allan.h5");
    bad << "garbage";
  }
  ASSERT_EQ(run_command(binary() + " export --format stable32 " + (d / "res").string() + " -o " +
                            (d / "partial.txt").string(),
                        &out),
            1);
  EXPECT_NE(out.find("zz_broken.allan.h5"), std::string::npos) << out;
  EXPECT_EQ(table_rows(test::file_bytes(d / "partial.txt")).size(), 3u * 8u);
}

TEST(Export, Errors) {
  const fs::path d = test::fresh_dir("export_errors");
  std::string out;
  EXPECT_EQ(run_command(binary() + " export " + (d / "none.allan.h5").string(), &out), 2);
  EXPECT_NE(out.find("none.allan.h5: no such file or directory"), std::string::npos) << out;
  EXPECT_EQ(run_command(binary() + " export " + d.string(), &out), 2);
  EXPECT_NE(out.find("no results files"), std::string::npos) << out;
  EXPECT_EQ(run_command(binary() + " export --format excel " + d.string(), &out), 2);
  {
    std::ofstream bad(d / "bad.allan.h5");
    bad << "garbage";
  }
  EXPECT_EQ(run_command(binary() + " export " + (d / "bad.allan.h5").string(), &out), 2);
  EXPECT_NE(out.find("bad.allan.h5"), std::string::npos) << out;
  EXPECT_EQ(run_command(binary() + " export --stats bogus " + (d / "bad.allan.h5").string(), &out),
            2);
  EXPECT_NE(out.find("unknown statistic 'bogus'"), std::string::npos) << out;
}

}  // namespace
}  // namespace allanlot
