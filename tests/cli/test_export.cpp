// `allanlot export`: Stable32 tables compared row by row with Stable32's own output for
// PHASE.DAT (AF, Tau, # and Alpha exact, Sigma to the printed digits, the bounds to 1 %), the
// tidy CSV's shape, and the errors.
#include "io/results.hpp"
#include "src/cli/export.hpp"
#include "support/h5_fixture.hpp"

#include <fstream>
#include <map>

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
  EXPECT_EQ(line, "device_id,channel,units,stat,m,tau,n,alpha,dev_lo,dev,dev_hi,edf,confidence,"
                  "dev_units");
  std::size_t rows = 0;
  bool found = false;
  while (std::getline(csv, line)) {
    ++rows;
    // A clock's time error in s: its deviations (oadev, mdev, ohdev here) are dimensionless.
    EXPECT_EQ(line.substr(line.rfind(',') + 1), "1") << line;
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

// The rules by which AllanTools' test helpers read a Stable32 table (tests/testutils.py,
// read_resultfile and read_stable32), restated: every line that does not start with '#' is
// split at single spaces, empty pieces dropped, and each piece must be a number (Python's
// float(), which allows surrounding blanks) or the reader fails; rows of 7 numbers are
// AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma, rows of 4 are AF, Tau, #, MTIE or TIE rms.
std::vector<std::vector<double>> allantools_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) continue;
    std::vector<double> row;
    std::size_t start = 0;
    for (;;) {
      const std::size_t space = line.find(' ', start);
      const std::string piece =
          line.substr(start, space == std::string::npos ? space : space - start);
      if (!piece.empty()) {
        std::size_t used = 0;
        const double v = std::stod(piece, &used);  // throws on "" and words, as float() does
        if (used != piece.size()) throw std::invalid_argument("not a number: " + piece);
        row.push_back(v);
      } else if (space == std::string::npos && row.empty()) {
        throw std::invalid_argument("a blank line");  // float("\n") fails in AllanTools
      }
      if (space == std::string::npos) break;
      start = space + 1;
    }
    rows.push_back(row);
  }
  return rows;
}

// The first lines of a Stable32 table, up to and with the column titles.
std::vector<std::string> head_lines(const std::string& text) {
  std::vector<std::string> head;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line) && line.starts_with("#");) {
    head.push_back(line);
    if (line.find("AF") != std::string::npos) break;
  }
  return head;
}

// Every all-tau and octave table of PHASE.DAT that Stable32 1.60 printed for the statistics
// allanlot computes, from `analyze --taus stable32` (and octave) and `export -o DIR`: the head
// (PHASE.DAT read as the text file it is), the column titles, AF, Tau and #
// print identically, Sigma but for one rounding tie; where Stable32 printed intervals (the octave
// runs), Alpha identically but where noted and the bounds within 1 % (their last digits are issue
// #19's); AllanTools' reader reads every table.
TEST(Export, Stable32TablesPrintAsStable32sOnPhaseDat) {
  const fs::path d = test::fresh_dir("export_stable32_layout");
  const std::string stats = "adev,oadev,mdev,tdev,hdev,ohdev,totdev";
  std::string out;
  std::size_t octave_rows = 0, alpha_differs = 0, sigma_differs = 0;
  for (const char* grid : {"stable32", "octave"}) {
    const fs::path res = d / grid, tables = d / (std::string(grid) + "_tables");
    fs::create_directories(tables);
    ASSERT_EQ(run_command(binary() + " analyze -q --no-fit --no-psd --stats " + stats + " --taus " +
                              grid + " --data-type phase --sample-rate 1 -o " + res.string() + " " +
                              (kStable32 / "PHASE.DAT").string(),
                          &out),
              0)
        << out;
    ASSERT_EQ(run_command(binary() + " export --format stable32 " + res.string() + " -o " +
                              tables.string(),
                          &out),
              0)
        << out;
    for (const char* stat : {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"}) {
      SCOPED_TRACE(std::string(grid) + " " + stat);
      const std::string ours =
          test::file_bytes(tables / cli::stable32_file_name("PHASE", "/data", stat));
      const std::string ref =
          test::file_bytes(kStable32 / ("phase_dat_" + std::string(stat) +
                                        (std::string(grid) == "octave" ? "_octave" : "") + ".txt"));
      auto ours_head = head_lines(ours), ref_head = head_lines(ref);
      // Stable32's octave files carry a line of their own ("# S32 1.60").
      std::erase_if(ref_head, [](const std::string& l) { return l.find("1.60") != l.npos; });
      ASSERT_EQ(ours_head.size(), ref_head.size());
      for (std::size_t i = 0; i < ref_head.size(); ++i)
        EXPECT_EQ(ours_head[i], ref_head[i]) << "head line " << i;
      const auto mine = table_rows(ours), theirs = table_rows(ref);
      ASSERT_EQ(mine.size(), theirs.size());
      for (std::size_t i = 0; i < theirs.size(); ++i) {
        for (std::size_t c : {0u, 1u, 2u})
          EXPECT_EQ(mine[i][c], theirs[i][c]) << "row " << i << " column " << c;
        if (mine[i][5] != theirs[i][5]) {
          ++sigma_differs;
          EXPECT_NEAR(std::stod(mine[i][5]), std::stod(theirs[i][5]),
                      1.01e-4 * std::stod(theirs[i][5]))
              << "row " << i;
        }
        // Stable32's all-tau runs print no interval (bounds and Alpha 0): nothing to compare.
        if (theirs[i][4] == "0.0000e+00") continue;
        // A row whose noise type differs (at most two, counted below) has the interval of
        // another noise type; test_confidence checks its bounds with Stable32's alpha.
        if (mine[i][3] != theirs[i][3]) {
          ++alpha_differs;
          continue;
        }
        for (std::size_t c : {4u, 6u})
          EXPECT_NEAR(std::stod(mine[i][c]), std::stod(theirs[i][c]),
                      0.01 * std::stod(theirs[i][c]))
              << "row " << i << " column " << c;
      }
      if (std::string(grid) == "octave") octave_rows += theirs.size();
      EXPECT_EQ(allantools_rows(ours).size(), theirs.size());
    }
  }
  // Noise identification at the two ends of the all-tau runs, where Stable32's lag-1
  // autocorrelation and allanlot's B1 ratio part (docs/statistics.md): at most 2 rows.
  EXPECT_LE(alpha_differs, 2u);
  // One Sigma of 1114 rows prints one unit of the last digit apart: TDEV at m = 47 is
  // 0.788355013 (to 1e-9 in long double, tests/kernels), 1.3e-8 above the rounding boundary,
  // and Stable32 prints 7.8835e-01; its own arithmetic lands below the boundary.
  EXPECT_LE(sigma_differs, 1u);
  // All tables in one file: parted by '#' lines, still read by AllanTools' rules.
  ASSERT_EQ(run_command(binary() + " export --format stable32 " + (d / "octave").string() + " -o " +
                            (d / "all.txt").string(),
                        &out),
            0)
      << out;
  EXPECT_EQ(allantools_rows(test::file_bytes(d / "all.txt")).size(), octave_rows);
}

// MTIE, TIE rms and Thêo1 from `analyze --taus stable32` on PHASE.DAT: every row of
// Stable32's tables is reprinted, with MTIE's and Thêo1's own averaging factors
// (kernels::stat_m_list), AF, Tau, # and the value exactly as Stable32 prints them (Thêo1's
// "#" rounded half up, as Stable32: 13 of its 181 counts are ties).
TEST(Export, Stable32OwnListsOfMtieTieRmsTheo1OnPhaseDat) {
  const fs::path d = test::fresh_dir("export_stable32_own_lists");
  const fs::path res = d / "res", tables = d / "tables";
  fs::create_directories(tables);
  std::string out;
  ASSERT_EQ(run_command(binary() +
                            " analyze -q --no-fit --no-psd --stats mtie,tierms,theo1 --taus "
                            "stable32 --data-type phase --sample-rate 1 -o " +
                            res.string() + " " + (kStable32 / "PHASE.DAT").string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(
      run_command(binary() + " export --format stable32 " + res.string() + " -o " + tables.string(),
                  &out),
      0)
      << out;
  const struct {
    const char* stat;
    const char* file;
    std::size_t columns, value;
  } cases[] = {{"mtie", "phase_dat_mtie.txt", 4, 3},
               {"tierms", "phase_dat_tierms.txt", 4, 3},
               {"theo1", "phase_dat_theo1_alpha0.txt", 7, 5}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.stat);
    const auto mine =
        table_rows(test::file_bytes(tables / cli::stable32_file_name("PHASE", "/data", c.stat)));
    const auto theirs = table_rows(test::file_bytes(kStable32 / c.file));
    ASSERT_GT(theirs.size(), 8u);
    if (std::string(c.stat) == "mtie") {  // Stable32's fast run, as the reference says
      EXPECT_NE(test::file_bytes(tables / cli::stable32_file_name("PHASE", "/data", c.stat))
                    .find("# Sigma Type: MTIE (Fast)\n"),
                std::string::npos);
    }
    ASSERT_EQ(mine.size(), theirs.size());
    for (std::size_t i = 0; i < theirs.size(); ++i) {
      ASSERT_EQ(mine[i].size(), c.columns) << "row " << i;
      ASSERT_EQ(theirs[i].size(), c.columns) << "row " << i;
      for (const std::size_t col : {std::size_t{0}, std::size_t{1}, std::size_t{2}, c.value})
        EXPECT_EQ(mine[i][col], theirs[i][col]) << "row " << i << " column " << col;
    }
  }
}

// Stable32's MTIE tables come in two kinds: the fast run (phase_dat_mtie.txt, "MTIE (Fast)",
// windows of 2^k points, "#" the N - m windows, up to m = N - 1), which `--taus stable32`
// reprints above, and the non-fast run on any other tau set, whose "#" is the N points
// analysed and whose rows stop at m = (N - 1) / 2 (Stable32's stop ratio 2: on a 5071A record
// its non-fast octave table ended one octave before N - 1). The same averaging factors as the
// fast table given as a list: the same MTIE values, "#" 1001 on every row, m = 511 left out.
TEST(Export, Stable32NonFastMtieOnPhaseDat) {
  const fs::path d = test::fresh_dir("export_stable32_mtie_slow");
  const fs::path res = d / "res", tables = d / "tables";
  fs::create_directories(tables);
  std::string out;
  ASSERT_EQ(run_command(binary() +
                            " analyze -q --no-fit --no-psd --stats mtie --taus "
                            "m:1,3,7,15,31,63,127,255,511 --data-type phase --sample-rate 1 -o " +
                            res.string() + " " + (kStable32 / "PHASE.DAT").string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(
      run_command(binary() + " export --format stable32 " + res.string() + " -o " + tables.string(),
                  &out),
      0)
      << out;
  const std::string ours =
      test::file_bytes(tables / cli::stable32_file_name("PHASE", "/data", "mtie"));
  EXPECT_NE(ours.find("# Sigma Type: MTIE\n"), std::string::npos) << ours;
  const auto mine = table_rows(ours);
  const auto fast = table_rows(test::file_bytes(kStable32 / "phase_dat_mtie.txt"));
  ASSERT_EQ(fast.size(), 9u);
  ASSERT_EQ(mine.size(), 8u);  // 511 > (1001 - 1) / 2
  for (std::size_t i = 0; i < mine.size(); ++i) {
    for (const std::size_t col : {std::size_t{0}, std::size_t{1}, std::size_t{3}})
      EXPECT_EQ(mine[i][col], fast[i][col]) << "row " << i << " column " << col;
    EXPECT_EQ(mine[i][2], "1001") << "row " << i;
  }
}

// A published non-fast Stable32 MTIE table: Stable32's decade run on 556 990 phase points of a
// 5071A caesium clock against an H-maser (tests/data/stable32/cs5071a, from AllanTools' test
// data). `--taus` given as its averaging factors, the non-fast layout ("#" the N points, rows to
// m = (N - 1) / 2: 200000 is the last decade factor below 278494); every line of Stable32's
// table is in ours, character for character, header and rows.
TEST(Export, Stable32NonFastMtieTableDiffsEqualOn5071A) {
  const fs::path cs = fs::path(ALLANLOT_REFERENCE_DIR) / "stable32" / "cs5071a";
  const fs::path d = test::fresh_dir("export_5071a_mtie");
  const fs::path res = d / "res", tables = d / "tables";
  fs::create_directories(tables);
  std::string out;
  // Unpacked first, so that the table is titled by the file Stable32 read.
  const fs::path phase = d / "5071A_phase.txt";
  ASSERT_EQ(run_command("gzip -dc " + (cs / "5071A_phase.txt.gz").string() + " > " + phase.string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(binary() +
                            " analyze -q --no-fit --no-psd --stats mtie --taus "
                            "m:1,2,4,10,20,40,100,200,400,1000,2000,4000,10000,20000,40000,"
                            "100000,200000,400000 --data-type phase --sample-rate 1 -o " +
                            res.string() + " " + phase.string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(
      run_command(binary() + " export --format stable32 " + res.string() + " -o " + tables.string(),
                  &out),
      0)
      << out;
  std::vector<std::string> written;
  for (const auto& e : fs::directory_iterator(tables))
    written.push_back(e.path().filename().string());
  ASSERT_EQ(written.size(), 1u);
  std::vector<std::string> ours;
  {
    std::istringstream in(test::file_bytes(tables / written[0]));
    for (std::string line; std::getline(in, line);)
      ours.push_back(line);
  }
  std::istringstream theirs(test::file_bytes(cs / "mtie_decade.txt"));
  std::size_t at = 0, lines = 0;
  for (std::string line; std::getline(theirs, line); ++lines) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
      line.pop_back();
    std::size_t i = at;
    while (i < ours.size() && ours[i] != line)
      ++i;
    EXPECT_LT(i, ours.size()) << "Stable32's line '" << line << "' is not in ours (after line "
                              << at << ")";
    if (i < ours.size()) at = i + 1;
  }
  EXPECT_EQ(lines, 26u);
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

// CSV fields of one line (no quoted commas in these tables).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');)
    f.push_back(x);
  if (!line.empty() && line.back() == ',') f.emplace_back();
  return f;
}

// `export --format readouts`: one row per channel and read-out, the numbers of the lot
// summary's readout columns (both from the results file), also for a term the fit does not
// detect (detected 0, with the reason).
TEST(Export, ReadoutsAsTidyCsv) {
  const fs::path d = test::fresh_dir("export_readouts");
  {
    std::ofstream m(d / "model.json");
    m << R"j({"sample_rate_hz": 100, "channels": {
          "gyro_x": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.00125}},
          "accel_x": {"units": "m/s^2", "terms": {"N": 0.0005}}}})j";
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " simulate -q --model " + (d / "model.json").string() +
                            " --duration 300 --seed 3 -o " + (d / "u1.h5").string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev --no-psd -o " + (d / "res").string() +
                            " " + (d / "u1.h5").string(),
                        &out),
            0)
      << out;
  const fs::path csv = d / "readouts.csv";
  ASSERT_EQ(run_command(binary() + " export --format readouts " + (d / "res").string() + " -o " +
                            csv.string(),
                        &out),
            0)
      << out;
  std::istringstream in(test::file_bytes(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "device_id,channel,units,readout,term,tau,value,sigma,unit,value_alt,sigma_alt,"
                  "unit_alt,detected,note");
  const auto rows = io::read_lot_summary(d / "res" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 2u);
  std::size_t n_rows = 0, undetected = 0;
  while (std::getline(in, line)) {
    const auto f = csv_fields(line);
    ASSERT_EQ(f.size(), 14u) << line;
    ++n_rows;
    const io::SummaryRow* r = nullptr;
    for (const auto& x : rows)
      if (x.device_id == f[0] && x.channel == f[1]) r = &x;
    ASSERT_NE(r, nullptr) << line;
    EXPECT_EQ(f[2], r->units);
    const auto near = [&](const std::string& text, double expected) {
      EXPECT_NEAR(std::stod(text), expected, 1e-10 * std::abs(expected)) << line;
    };
    if (f[3] == "N_1s") {
      EXPECT_EQ(f[4], "N");
      near(f[6], r->readout_n);
      near(f[7], r->readout_n_sigma);
      EXPECT_EQ(f[8], r->readout_n_unit);
      near(f[9], r->readout_n_alt);  // ARW or VRW
      near(f[10], r->readout_n_alt_sigma);
      EXPECT_EQ(f[11], r->readout_n_alt_unit);
      EXPECT_TRUE(f[11] == "deg/sqrt(h)" || f[11] == "m/s/sqrt(h)") << line;
    } else if (f[3] == "bias_instability") {
      EXPECT_EQ(f[4], "B");
      near(f[5], r->readout_b_tau);
      near(f[6], r->readout_b);
      EXPECT_EQ(f[8], r->readout_b_unit);
    } else {
      ASSERT_EQ(f[3], "K_3s") << line;
      near(f[5], r->readout_k_tau);
      near(f[6], r->readout_k);
      EXPECT_EQ(f[8], r->readout_k_unit);
    }
    // Detected as readouts_valid says; an undetected one says why.
    const bool valid = (" " + r->readouts_valid + " ").find(" " + f[4] + " ") != std::string::npos;
    EXPECT_EQ(f[12], valid ? "1" : "0") << line;
    EXPECT_EQ(f[13].empty(), valid) << line;
    if (!valid) {
      ++undetected;
      EXPECT_NE(f[13].find("the fit does not detect " + f[4]), std::string::npos) << line;
    }
  }
  EXPECT_EQ(n_rows, 6u);      // three read-outs of two channels
  EXPECT_GE(undetected, 1u);  // K is in neither model
  // --stats selects deviation tables, which this format has not.
  EXPECT_EQ(run_command(
                binary() + " export --format readouts --stats oadev " + (d / "res").string(), &out),
            2);
  EXPECT_NE(out.find("--format readouts"), std::string::npos) << out;
}

}  // namespace
}  // namespace allanlot
