// End-to-end tests of `allanlot analyze` through the real binary: results layout, exit
// statuses, bad inputs, thread invariance, inputs never modified.
#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan/allan.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

std::vector<double> noise(std::size_t n, double offset, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  double walk = 0;
  for (auto& x : v) {
    walk += 1e-3 * g(rng);
    x = offset + 0.01 * g(rng) + walk;
  }
  return v;
}

// A unit file in the simulate layout with two gyro channels and a float32 accelerometer.
void write_unit(const fs::path& path, const std::string& device_id, unsigned seed,
                std::size_t n = 20000) {
  test::H5Fixture f(path);
  f.dataset("/imu/gyro_x", noise(n, 0.1, seed), H5T_IEEE_F64LE);
  f.dataset("/imu/gyro_y", noise(n, -0.2, seed + 1), H5T_IEEE_F64LE);
  f.dataset("/imu/accel_z", noise(n, 9.80665, seed + 2), H5T_IEEE_F32LE);
  f.attr("/imu", "sample_rate_hz", 100.0);
  f.attr("/imu", "units", "deg/s");
  f.attr("/imu/accel_z", "units", "m/s^2");
  if (!device_id.empty()) f.attr("/", "device_id", device_id);
}

const io::ChannelResult& channel(const io::RecordingResult& r, const std::string& path) {
  for (const auto& c : r.channels)
    if (c.path == path) return c;
  throw std::runtime_error("no channel " + path);
}

TEST(Analyze, WritesContractLayoutAndMatchesKernels) {
  const auto dir = test::fresh_dir("analyze_layout");
  write_unit(dir / "u1.h5", "UNIT-1", 1);
  const std::string before = test::file_bytes(dir / "u1.h5");
  std::string out;
  const int rc = run_command(binary() + " analyze --stats oadev --taus octave -o " +
                                 (dir / "out").string() + " " + (dir / "u1.h5").string(),
                             &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("lot_summary.csv"), std::string::npos);
  EXPECT_EQ(test::file_bytes(dir / "u1.h5"), before);  // the input is never modified

  const auto r = io::read_results(dir / "out" / "UNIT-1.allan.h5");
  EXPECT_EQ(r.device_id, "UNIT-1");
  EXPECT_NE(r.command_line.find("analyze"), std::string::npos);
  EXPECT_FALSE(r.tool_version.empty());
  EXPECT_FALSE(r.created_utc.empty());
  ASSERT_EQ(r.channels.size(), 3u);
  const auto& az = channel(r, "/imu/accel_z");
  EXPECT_EQ(az.units, "m/s^2");
  EXPECT_EQ(az.sample_rate_hz, 100.0);
  EXPECT_EQ(az.n_samples, 20000);
  EXPECT_EQ(io::to_string(az.status), "ok");
  ASSERT_EQ(az.stats.size(), 1u);
  EXPECT_EQ(az.stats[0].first, "oadev");

  // The same numbers as the kernels applied to the data read back through io.
  io::RecordingReader reader((dir / "u1.h5").string());
  for (const auto& info : reader.info().channels) {
    const auto p = kernels::phase_from_rate(reader.read(info), info.sample_rate_hz, 1);
    const auto ms = kernels::make_m_list(kernels::parse_tau_grid("octave"),
                                         kernels::max_m(kernels::Stat::Oadev, p.n_points()));
    const auto expected = kernels::oadev(p, ms, 1);
    const auto& got = channel(r, info.path).stats[0].second;
    EXPECT_EQ(got.m, expected.m);
    EXPECT_EQ(got.n, expected.n);
    EXPECT_EQ(got.tau_s, expected.tau_s);
    EXPECT_EQ(got.dev, expected.dev) << info.path;
  }

  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.device_id, "UNIT-1");
    EXPECT_EQ(io::to_string(row.status), "ok");
    EXPECT_EQ(row.n_samples, 20000);
  }
}

TEST(Analyze, SameResultsForOneAndTwoThreads) {
  const auto dir = test::fresh_dir("analyze_threads");
  write_unit(dir / "u.h5", "", 5, 60000);
  for (const char* t : {"1", "2"})
    ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev --taus log:20 --threads " + t +
                          " -o " + (dir / ("out" + std::string(t))).string() + " " +
                          (dir / "u.h5").string()),
              0);
  const auto a = io::read_results(dir / "out1" / "u.allan.h5");
  const auto b = io::read_results(dir / "out2" / "u.allan.h5");
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (const auto& ca : a.channels) {
    const auto& cb = channel(b, ca.path);
    ASSERT_EQ(ca.stats.size(), cb.stats.size());
    for (std::size_t i = 0; i < ca.stats.size(); ++i) {
      EXPECT_EQ(ca.stats[i].second.dev, cb.stats[i].second.dev);  // bit for bit
      EXPECT_EQ(ca.stats[i].second.n, cb.stats[i].second.n);
    }
  }
}

TEST(Analyze, SomeInputsFailOthersAreAnalysed) {
  const auto dir = test::fresh_dir("analyze_partial");
  write_unit(dir / "good.h5", "", 2);
  { std::ofstream(dir / "junk.h5") << "garbage"; }
  {
    test::H5Fixture f(dir / "nochan.h5");
    f.dataset("/x", {1, 2, 3}, H5T_IEEE_F64LE);
  }
  {
    test::H5Fixture f(dir / "short.h5");
    f.dataset("/imu/gyro_x", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 10.0);
  }
  std::string out;
  const int rc =
      run_command(binary() + " analyze -q --stats oadev -o " + (dir / "out").string() + " " +
                      (dir / "good.h5").string() + " " + (dir / "junk.h5").string() + " " +
                      (dir / "nochan.h5").string() + " " + (dir / "short.h5").string() + " " +
                      (dir / "missing.h5").string(),
                  &out);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find((dir / "junk.h5").string() + ": not an HDF5 file"), std::string::npos) << out;
  EXPECT_NE(out.find((dir / "nochan.h5").string() + ": no channel found"), std::string::npos)
      << out;
  EXPECT_NE(out.find((dir / "short.h5").string()), std::string::npos) << out;
  EXPECT_NE(out.find("/imu/gyro_x"), std::string::npos) << out;
  EXPECT_NE(out.find("too short"), std::string::npos) << out;
  EXPECT_NE(out.find((dir / "missing.h5").string() + ": no such file"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "good.allan.h5"));
  for (const char* name : {"junk", "nochan", "short", "missing"})
    EXPECT_FALSE(fs::exists(dir / "out" / (std::string(name) + ".allan.h5"))) << name;
  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  int failed = 0, ok = 0;
  for (const auto& r : rows)
    (io::to_string(r.status) == "ok" ? ok : failed) += 1;
  EXPECT_EQ(ok, 3);
  EXPECT_EQ(failed, 4);
  // No temporary file is left behind.
  for (const auto& e : fs::directory_iterator(dir / "out"))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST(Analyze, UsageErrorsExitTwo) {
  const auto dir = test::fresh_dir("analyze_usage");
  write_unit(dir / "u.h5", "", 3, 2000);
  const std::string in = ' ' + (dir / "u.h5").string();
  const std::string o = std::string(" -o ").append((dir / "out").string());
  std::string out;
  EXPECT_EQ(run_command(binary() + " analyze --stats bogus" + o + in, &out), 2);
  EXPECT_NE(out.find("unknown statistic 'bogus'"), std::string::npos) << out;
  EXPECT_EQ(run_command(binary() + " analyze --taus log:0" + o + in, &out), 2);
  EXPECT_NE(out.find("--taus"), std::string::npos) << out;
  EXPECT_EQ(run_command(binary() + " analyze" + in, &out), 2);  // no -o
  EXPECT_EQ(run_command(binary() + " analyze" + o, &out), 2);   // no input
  EXPECT_EQ(run_command(binary() + " frobnicate", &out), 2);    // no such command
  EXPECT_EQ(run_command(binary() + " analyze --threads -3" + o + in, &out), 2);
  { std::ofstream(dir / "afile") << "x"; }
  EXPECT_EQ(
      run_command(binary() + " analyze --stats oadev -o " + (dir / "afile").string() + in, &out),
      2);
  EXPECT_NE(out.find("not a directory"), std::string::npos) << out;
  // Nothing analysable at all: 2.
  EXPECT_EQ(
      run_command(binary() + " analyze --stats oadev" + o + " " + (dir / "missing.h5").string(),
                  &out),
      2);
  EXPECT_EQ(run_command(binary() + " --version", &out), 0);
  EXPECT_EQ(run_command(binary() + " analyze --help", &out), 0);
  EXPECT_NE(out.find("--taus"), std::string::npos);
}

// The lot summary never replaces an input: `analyze -o d d/lot_summary.csv` (a text recording
// that happens to bear the name) and `d/lot_summary.h5` (a recording) are usage errors before any
// work, the input byte for byte as it was.
TEST(Analyze, ALotSummaryNamingAnInputIsAUsageError) {
  const auto dir = test::fresh_dir("analyze_summary_is_input");
  fs::create_directories(dir / "d");
  write_unit(dir / "d" / "lot_summary.h5", "", 3, 2000);
  {
    std::ofstream csv(dir / "d" / "lot_summary.csv");
    for (int i = 0; i < 2000; ++i)
      csv << 0.01 * ((i * 7919) % 101 - 50) << "\n";
  }
  for (const char* name : {"lot_summary.csv", "lot_summary.h5"}) {
    const fs::path input = dir / "d" / name;
    const std::string before = test::file_bytes(input);
    std::string out;
    EXPECT_EQ(run_command(binary() + " analyze -q --sample-rate 100 --data-type rate -o " +
                              (dir / "d").string() + " " + input.string(),
                          &out),
              2)
        << out;
    EXPECT_NE(out.find("it would be overwritten"), std::string::npos) << out;
    EXPECT_EQ(test::file_bytes(input), before) << name;
    EXPECT_FALSE(fs::exists(dir / "d" / "lot_summary.allan.h5"));
  }
  // Through another spelling of OUTDIR, too.
  std::string out;
  EXPECT_EQ(run_command(binary() + " analyze -q -o " + (dir / "d" / "." / "").string() + " " +
                            (dir / "d" / "lot_summary.h5").string(),
                        &out),
            2)
      << out;
}

// A chunked dataset may declare any length in a few bytes: 2^57 to 2^60 samples fail the memory
// check by name (32 bytes a sample times 2^59 once wrapped to 0 and the division by it was a
// SIGFPE), more than 2^60 fail as beyond any memory; the lot goes on.
TEST(Analyze, HugeDeclaredLengthsFailTheirChannelWithoutOverflow) {
  const auto dir = test::fresh_dir("analyze_huge_lengths");
  const int exponents[] = {57, 58, 59, 60, 61, 62};
  for (const int e : exponents) {
    const fs::path p = dir / ("huge_" + std::to_string(e) + ".h5");
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = hsize_t{1} << e, max = H5S_UNLIMITED, chunk = 1024;
    const hid_t space = H5Screate_simple(1, &n, &max);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, &chunk);
    const hid_t ds = H5Dcreate2(f, "gyro_x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    const double rate = 100.0;
    const hid_t aspace = H5Screate(H5S_SCALAR);
    const hid_t a =
        H5Acreate2(ds, "sample_rate_hz", H5T_IEEE_F64LE, aspace, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, &rate);
    H5Aclose(a);
    H5Sclose(aspace);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Fclose(f);
  }
  write_unit(dir / "good.h5", "", 3, 2000);
  std::string out;
  EXPECT_EQ(run_command(binary() + " analyze -q --no-psd --taus octave --memory-limit 1G -o " +
                            (dir / "out").string() + " " + dir.string(),
                        &out),
            1)
      << out;
  for (const int e : exponents) {
    const std::string n = std::to_string(std::uint64_t{1} << e);
    EXPECT_NE(out.find("huge_" + std::to_string(e) + ".h5:/gyro_x: " +
                       (e <= 60 ? n + " samples need about" : "declares " + n + " samples")),
              std::string::npos)
        << e << ":\n"
        << out;
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "good.allan.h5"));
}

TEST(Analyze, DirectoriesManifestsAndDeviceIds) {
  const auto dir = test::fresh_dir("analyze_inputs");
  fs::create_directories(dir / "lot" / "sub");
  write_unit(dir / "lot" / "a.h5", "", 10, 3000);
  write_unit(dir / "lot" / "sub" / "b.hdf5", "../../escape", 11, 3000);
  write_unit(dir / "c.h5", "", 12, 3000);
  write_unit(dir / "c2.h5", "c", 13, 3000);  // same device_id as c.h5
  {
    std::ofstream m(dir / "manifest.txt");
    m << "# a manifest\n\nc.h5\n  c2.h5  \n";
  }
  std::string out;
  const int rc =
      run_command(binary() + " analyze -q --stats oadev -o " + (dir / "out").string() + " " +
                      (dir / "lot").string() + " @" + (dir / "manifest.txt").string(),
                  &out);
  EXPECT_EQ(rc, 1) << out;  // c2.h5 collides with c.h5
  EXPECT_NE(out.find("device_id 'c'"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "a.allan.h5"));
  EXPECT_TRUE(fs::exists(dir / "out" / "c.allan.h5"));
  EXPECT_TRUE(fs::exists(dir / "out" / "_._.._escape.allan.h5"));  // stays inside OUTDIR
  EXPECT_FALSE(fs::exists(dir / "escape.allan.h5"));
  EXPECT_EQ(io::read_results(dir / "out" / "_._.._escape.allan.h5").device_id, "../../escape");
}

TEST(Analyze, ChannelGlobAndSummarize) {
  const auto dir = test::fresh_dir("analyze_glob");
  write_unit(dir / "u.h5", "", 20, 3000);
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev --channels 'gyro_*' -o " +
                        (dir / "out").string() + " " + (dir / "u.h5").string()),
            0);
  const auto r = io::read_results(dir / "out" / "u.allan.h5");
  EXPECT_EQ(r.channels.size(), 2u);
  fs::remove(dir / "out" / "lot_summary.h5");
  fs::remove(dir / "out" / "lot_summary.csv");
  std::string out;
  ASSERT_EQ(run_command(binary() + " summarize " + (dir / "out").string(), &out), 0) << out;
  EXPECT_EQ(io::read_lot_summary(dir / "out" / "lot_summary.h5").size(), 2u);
  EXPECT_EQ(run_command(binary() + " analyze -q --stats oadev --channels 'nothing*' -o " +
                            (dir / "out2").string() + " " + (dir / "u.h5").string(),
                        &out),
            2);
  EXPECT_NE(out.find("no channel matches"), std::string::npos) << out;
}

}  // namespace
}  // namespace allanlot

namespace allanlot {
namespace {

// A channel with gaps under --gaps skip: every statistic that can leave out the terms touching a
// gap does, and totdev, which cannot, is skipped with a note instead of failing the channel.
TEST(Analyze, GappedChannelSkipsTotdevWithANote) {
  const auto dir = test::fresh_dir("analyze_gaps");
  auto v = noise(20000, 0.0, 31);
  for (const std::size_t i : {100u, 5000u, 5001u, 17000u})
    v[i] = std::nan("");
  {
    test::H5Fixture f(dir / "g.h5");
    f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze --gaps skip --stats oadev,totdev --taus octave -o " +
                            (dir / "out").string() + " " + (dir / "g.h5").string(),
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("totdev not computed"), std::string::npos) << out;
  const auto r = io::read_results(dir / "out" / "g.allan.h5");
  ASSERT_EQ(r.channels.size(), 1u);
  const auto& ch = r.channels[0];
  EXPECT_EQ(io::to_string(ch.status), "ok");
  EXPECT_EQ(ch.n_gaps, 4);
  EXPECT_NE(ch.notes.find("totdev"), std::string::npos);
  ASSERT_EQ(ch.stats.size(), 1u);
  EXPECT_EQ(ch.stats[0].first, "oadev");
  EXPECT_LT(ch.stats[0].second.n[0], 20000);  // terms touching the gaps left out
  EXPECT_TRUE(ch.fit.has_value());
  EXPECT_EQ(ch.gap_policy, "skip");
  EXPECT_EQ(ch.n_filled, 0);
  EXPECT_EQ(ch.gap_runs_left, 3);
}

// The default policy on the same kind of channel: the short runs are filled, every row keeps at
// least 99 % of the terms without gaps and the longest taus all of them, totdev runs with every
// term, and the channel says what was filled; a run longer than fill:N stays a gap; an unknown
// policy is a usage error (status 2).
TEST(Analyze, DefaultGapPolicyFillsShortRunsAndSaysSo) {
  const auto dir = test::fresh_dir("analyze_gaps_fill");
  const auto clean = noise(20000, 0.0, 31);
  auto v = clean;
  for (const std::size_t i : {100u, 5000u, 5001u, 17000u})
    v[i] = std::nan("");
  {
    test::H5Fixture f(dir / "g.h5");
    f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
    test::H5Fixture c(dir / "c.h5");
    c.dataset("/imu/gyro_x", clean, H5T_IEEE_F64LE);
    c.attr("/imu", "sample_rate_hz", 100.0);
  }
  const std::string cmd = binary() + " analyze --stats oadev,totdev --taus octave --no-psd";
  std::string out;
  ASSERT_EQ(run_command(cmd + " -o " + (dir / "out").string() + " " + (dir / "g.h5").string() +
                            " " + (dir / "c.h5").string(),
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("4 missing samples in 3 runs; 4 filled by interpolation in 3 runs"),
            std::string::npos)
      << out;
  const auto g = io::read_results(dir / "out" / "g.allan.h5").channels.at(0);
  const auto c = io::read_results(dir / "out" / "c.allan.h5").channels.at(0);
  EXPECT_EQ(g.n_gaps, 4);
  EXPECT_EQ(g.gap_policy, "fill:10");
  EXPECT_EQ(g.n_filled, 4);
  EXPECT_EQ(g.filled_runs, 3);
  EXPECT_EQ(g.gap_runs_left, 0);
  EXPECT_TRUE(c.gap_policy.empty());  // a gap-free channel carries no account
  ASSERT_EQ(g.stats.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const auto &gs = g.stats[k].second, &cs = c.stats[k].second;
    EXPECT_EQ(g.stats[k].first, c.stats[k].first);
    ASSERT_EQ(gs.m, cs.m) << g.stats[k].first;
    EXPECT_EQ(gs.n.back(), cs.n.back()) << g.stats[k].first;
    for (std::size_t i = 0; i < gs.size(); ++i)
      EXPECT_GE(gs.n[i], 0.99 * static_cast<double>(cs.n[i])) << g.stats[k].first;
  }
  EXPECT_EQ(g.stats[1].second.n, c.stats[1].second.n);  // totdev: on the filled record
  ASSERT_EQ(run_command(binary() + " analyze --gaps fill:1 --stats oadev,totdev --taus octave " +
                            "--no-psd -o " + (dir / "out1").string() + " " +
                            (dir / "g.h5").string(),
                        &out),
            0)
      << out;
  const auto g1 = io::read_results(dir / "out1" / "g.allan.h5").channels.at(0);
  EXPECT_EQ(g1.gap_policy, "fill:1");
  EXPECT_EQ(g1.n_filled, 2);
  EXPECT_EQ(g1.gap_runs_left, 1);
  EXPECT_NE(g1.notes.find("totdev not computed"), std::string::npos) << g1.notes;
  for (const char* bad : {"fill:0", "fil", "skip:2"}) {
    EXPECT_EQ(run_command(cmd + " --gaps " + bad + " -o " + (dir / "bad").string() + " " +
                              (dir / "g.h5").string(),
                          &out),
              2)
        << bad;
    EXPECT_NE(out.find("--gaps"), std::string::npos) << out;
  }
}

// --stats all: every statistic of the build is written to allan/<stat>/ and read back, each
// equal to kernels::compute on the same phase; those without an interval carry NaN bounds.
TEST(Analyze, StatsAllWritesEveryStatistic) {
  const auto dir = test::fresh_dir("analyze_all");
  {
    test::H5Fixture f(dir / "a.h5");
    f.dataset("/imu/gyro_x", noise(3000, 0.1, 41), H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --stats all --taus octave --no-fit --no-psd -o " +
                            (dir / "out").string() + " " + (dir / "a.h5").string(),
                        &out),
            0)
      << out;
  const auto r = io::read_results(dir / "out" / "a.allan.h5");
  ASSERT_EQ(r.channels.size(), 1u);
  const auto& ch = r.channels[0];
  ASSERT_EQ(ch.stats.size(), kernels::all_stats().size());
  const auto phase =
      kernels::phase_from_rate(noise(3000, 0.1, 41), 100.0, 1);  // the channel's phase
  for (const auto& [name, s] : ch.stats) {
    const auto stat = kernels::parse_stat(name);
    ASSERT_TRUE(stat.has_value()) << name;
    const auto ms = kernels::make_m_list(kernels::parse_tau_grid("octave"),
                                         kernels::max_m(*stat, phase.n_points()), phase.n_points());
    const auto k = kernels::compute(*stat, phase, ms, 1);
    EXPECT_EQ(s.m, k.m) << name;
    ASSERT_EQ(s.dev.size(), k.dev.size()) << name;
    // htotdev is written bias-corrected (kernels::add_confidence), tdev derived from mdev's
    // sums (src/pipeline/channel.cpp: the last bits differ); the others exactly as computed.
    if (*stat == kernels::Stat::Tdev) {
      for (std::size_t i = 0; i < s.size(); ++i)
        EXPECT_NEAR(s.dev[i] / k.dev[i], 1.0, 1e-14) << name;
    } else if (*stat != kernels::Stat::Htotdev) {
      EXPECT_EQ(s.dev, k.dev) << name;
    }
    ASSERT_EQ(s.dev_lo.size(), s.dev.size()) << name;
    for (std::size_t i = 0; i < s.size(); ++i)
      EXPECT_EQ(std::isnan(s.dev_lo[i]), !kernels::has_interval(*stat)) << name;
  }
  // A gapped channel under --gaps skip: the statistics that refuse gaps are skipped with a note
  // each.
  auto v = noise(3000, 0.0, 42);
  v[1000] = std::nan("");
  {
    test::H5Fixture f(dir / "g.h5");
    f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  ASSERT_EQ(run_command(binary() + " analyze -q --gaps skip --stats all --taus octave --no-fit " +
                            "--no-psd -o " + (dir / "outg").string() + " " +
                            (dir / "g.h5").string(),
                        &out),
            0)
      << out;
  const auto g = io::read_results(dir / "outg" / "g.allan.h5");
  std::size_t gap_ok = 0;
  for (const auto s : kernels::all_stats())
    gap_ok += kernels::supports_gaps(s) ? 1 : 0;
  EXPECT_EQ(g.channels[0].stats.size(), gap_ok);
  EXPECT_NE(g.channels[0].notes.find("theo1 not computed"), std::string::npos);
}

// A statistic asked for a record it does not apply to is a per-channel
// outcome, never a crash. Thêo1 needs 11 phase points (m = 10): on 8 samples it has no row; with
// OADEV beside it the channel is ok and theo1's group is empty; alone, the channel fails with
// its reason, and with nothing analysed the run ends with status 2 (docs/cli.md "Exit status").
TEST(Analyze, Theo1OnTooShortARecordIsAChannelOutcome) {
  const auto dir = test::fresh_dir("analyze_theo1_short");
  {
    test::H5Fixture f(dir / "s.h5");
    f.dataset("/imu/gyro_x", noise(8, 0.1, 43), H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --stats oadev,theo1 --no-fit --no-psd -o " +
                            (dir / "both").string() + " " + (dir / "s.h5").string(),
                        &out),
            0)
      << out;
  const auto r = io::read_results(dir / "both" / "s.allan.h5");
  ASSERT_EQ(r.channels.size(), 1u);
  for (const auto& [name, s] : r.channels[0].stats)
    EXPECT_EQ(s.size() == 0, name == "theo1") << name;
  EXPECT_EQ(run_command(binary() + " analyze -q --stats theo1 --no-fit --no-psd -o " +
                            (dir / "alone").string() + " " + (dir / "s.h5").string(),
                        &out),
            2)
      << out;
  EXPECT_NE(out.find("too short for any tau of the requested statistics"), std::string::npos)
      << out;
}

// Clock data get a deviation table in the terminal, not the IMU term table: a unit with a clock
// (phase data in s, a random-walk phase with white noise) and a gyro prints the gyro's eq. (3)
// table and, for the clock, tau and each statistic with its bounds, the values those of the
// results file.
TEST(Analyze, ClockDataGetADeviationTable) {
  const fs::path d = test::fresh_dir("analyze_clock_table");
  {
    test::H5Fixture f(d / "osc.h5");
    // Time error in ns (read as s, scaled by 1e-9): white and random-walk phase.
    f.dataset("/clock/phase", noise(4000, 0.0, 3), H5T_IEEE_F64LE);
    f.attr("/clock/phase", "sample_rate_hz", 1.0);
    f.attr("/clock/phase", "data_type", std::string("phase"));
    f.attr("/clock/phase", "units", std::string("ns"));
    f.dataset("/imu/gyro_x", noise(4000, 0.1, 4), H5T_IEEE_F64LE);
    f.attr("/imu/gyro_x", "sample_rate_hz", 100.0);
    f.attr("/imu/gyro_x", "units", std::string("deg/s"));
    f.attr("/", "device_id", std::string("OSC1"));
  }
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze --no-psd --stats oadev,mdev,tdev --taus octave -o " +
                            (d / "res").string() + " " + (d / "osc.h5").string(),
                        &out),
            0)
      << out;
  // The gyro keeps the term table; the clock is not in it.
  const auto terms = out.find("OSC1: noise coefficients of eq. (3)");
  ASSERT_NE(terms, std::string::npos) << out;
  const auto clock = out.find("OSC1: /clock/phase (clock data, phase, units 's'): deviations");
  ASSERT_NE(clock, std::string::npos) << out;
  const std::string term_table = out.substr(terms, clock - terms);
  EXPECT_NE(term_table.find("gyro_x"), std::string::npos) << term_table;
  EXPECT_EQ(term_table.find("phase"), std::string::npos) << term_table;
  std::istringstream table(out.substr(clock));
  std::string line;
  std::getline(table, line);
  EXPECT_NE(line.find("fractional frequency (dimensionless); time errors in s"), std::string::npos)
      << line;
  std::getline(table, line);
  std::istringstream header(line);
  std::vector<std::string> columns;
  for (std::string w; header >> w;)
    columns.push_back(w);
  EXPECT_EQ(columns, (std::vector<std::string>{"tau", "[s]", "oadev", "mdev", "tdev"})) << line;
  // Each row: tau, then "dev [lo, hi]" per statistic, as in the results file.
  const io::RecordingResult r = io::read_results(d / "res" / "OSC1.allan.h5");
  const io::ChannelResult& ch = channel(r, "/clock/phase");
  const kernels::StatResult& oadev = ch.stats[0].second;
  const kernels::StatResult& tdev = ch.stats[2].second;
  ASSERT_EQ(ch.stats[2].first, "tdev");
  // "dev [lo, hi]", or the value alone where the interval has no bounds.
  const auto cell = [](const kernels::StatResult& st, std::size_t i) {
    char text[160];
    if (std::isfinite(st.dev_lo[i]) && std::isfinite(st.dev_hi[i]))
      std::snprintf(text, sizeof text, "%.3g [%.2g, %.2g]", st.dev[i], st.dev_lo[i], st.dev_hi[i]);
    else
      std::snprintf(text, sizeof text, "%.3g", st.dev[i]);
    return std::string(text);
  };
  ASSERT_GT(oadev.size(), 3u);
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    ASSERT_TRUE(std::getline(table, line)) << "row " << i;
    char tau[32];
    std::snprintf(tau, sizeof tau, "%.4g", oadev.tau_s[i]);
    EXPECT_EQ(line.rfind("  " + std::string(tau) + " ", 0), 0u) << line;
    EXPECT_NE(line.find(cell(oadev, i)), std::string::npos) << line << " vs " << cell(oadev, i);
    for (std::size_t j = 0; j < tdev.size(); ++j) {
      if (tdev.tau_s[j] == oadev.tau_s[i]) {
        EXPECT_NE(line.find(cell(tdev, j)), std::string::npos) << line << " vs " << cell(tdev, j);
      }
    }
  }
  EXPECT_TRUE(std::isfinite(oadev.dev_lo[0]));  // the bounds are there to be shown
}

}  // namespace
}  // namespace allanlot

namespace allanlot {
namespace {

// `--si` prints the coefficient table in rad/s and m/s^2 and seconds: the gyro's N is its
// stored value (deg/s*s^0.5) times pi/180, the accelerometer's its stored value.
TEST(Analyze, SiTableInRadiansAndMetres) {
  const auto dir = test::fresh_dir("analyze_si");
  write_unit(dir / "u1.h5", "UNIT-SI", 3);
  std::string si, plain;
  const std::string args = " analyze --stats oadev -o " + (dir / "out").string() + " --force " +
                           (dir / "u1.h5").string();
  ASSERT_EQ(run_command(binary() + args + " --si", &si), 0) << si;
  ASSERT_EQ(run_command(binary() + args, &plain), 0) << plain;
  EXPECT_NE(si.find("in SI units"), std::string::npos) << si;
  EXPECT_NE(si.find("rad/s*s^0.5"), std::string::npos) << si;
  EXPECT_NE(si.find("m/s^2*s^0.5"), std::string::npos) << si;
  EXPECT_EQ(plain.find("rad/s*s^0.5"), std::string::npos) << plain;
  EXPECT_NE(plain.find("deg/h/sqrt(Hz)"), std::string::npos) << plain;
  const auto r = io::read_results(dir / "out" / "UNIT-SI.allan.h5");
  for (const auto& [path, factor] :
       {std::pair<std::string, double>{"/imu/gyro_x", std::numbers::pi / 180.0},
        {"/imu/accel_z", 1.0}}) {
    const auto& terms = channel(r, path).fit->terms;
    const auto n = std::find_if(terms.begin(), terms.end(),
                                [](const io::TermRecord& t) { return t.term == "N"; });
    ASSERT_NE(n, terms.end());
    ASSERT_TRUE(n->detected);
    char cell[64];
    std::snprintf(cell, sizeof cell, "%.3g ± %.2g", n->value * factor, n->sigma * factor);
    EXPECT_NE(si.find(cell), std::string::npos) << path << " " << cell << "\n" << si;
  }
}

}  // namespace
}  // namespace allanlot
