// `allanlot hat` and `allanlot codev` through the binary: the results file holds what the
// kernels compute (bit for bit, for any thread count), sealed; codev of a record with itself is
// its OADEV; bad inputs are usage errors (exit 2) naming the file and the reason, with nothing
// written.
#include "io/error.hpp"
#include "io/results.hpp"
#include "io/seal.hpp"
#include "io/stat_group.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/hat.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

namespace allanlot {
namespace {

using test::binary;
using test::run_command;

std::vector<double> white(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> d(0.0, sigma);
  std::vector<double> v(n);
  for (double& s : v)
    s = d(gen);
  return v;
}

// A phase recording: /clock/phase (s) at `rate_hz`, optionally a second channel.
void write_phase(const std::filesystem::path& file, const std::vector<double>& x,
                 double rate_hz = 1.0, bool second_channel = false, const std::string& units = "s",
                 const std::string& data_type = "phase") {
  test::H5Fixture f(file);
  f.group("/clock");
  f.attr("/clock", "sample_rate_hz", rate_hz);
  f.dataset("/clock/phase", x, H5T_IEEE_F64LE);
  f.attr("/clock/phase", "units", units);
  f.attr("/clock/phase", "data_type", data_type);
  if (second_channel) {
    f.dataset("/clock/other", x, H5T_IEEE_F64LE);
    f.attr("/clock/other", "data_type", "phase");
  }
}

// Three clocks of white PM (1, 2, 3) and the records of their pairwise differences.
struct Clocks {
  std::vector<double> ab, bc, ca;
};
Clocks clocks(std::size_t n) {
  const auto a = white(n, 1.0, 1), b = white(n, 2.0, 2), c = white(n, 3.0, 3);
  Clocks k{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    k.ab[i] = a[i] - b[i];
    k.bc[i] = b[i] - c[i];
    k.ca[i] = c[i] - a[i];
  }
  return k;
}

struct Fixture {
  std::filesystem::path dir, ab, bc, ca;
  Clocks k;
};
Fixture make_fixture(const std::string& name, std::size_t n = 6000) {
  Fixture f{test::fresh_dir(name), {}, {}, {}, clocks(n)};
  f.ab = f.dir / "ab.h5";
  f.bc = f.dir / "bc.h5";
  f.ca = f.dir / "ca.h5";
  write_phase(f.ab, f.k.ab);
  write_phase(f.bc, f.k.bc);
  write_phase(f.ca, f.k.ca);
  return f;
}

const kernels::StatResult& stat_of(const io::RecordingResult& r, const std::string& channel) {
  for (const auto& ch : r.channels)
    if (ch.path == channel) return ch.stats.at(0).second;
  throw std::runtime_error("no channel " + channel);
}

TEST(HatCommand, WritesEachClockAsTheKernelComputesIt) {
  const auto f = make_fixture("hat_cli");
  const auto out = f.dir / "hat.h5";
  std::string text;
  ASSERT_EQ(run_command(binary() + " hat --taus octave --threads 2 " + f.ab.string() + " " +
                            f.bc.string() + " " + f.ca.string() + " -o " + out.string(),
                        &text),
            0)
      << text;
  EXPECT_EQ(io::check_seal(out).state, io::SealState::Intact);
  const io::RecordingResult r = io::read_results(out);
  ASSERT_EQ(r.channels.size(), 6u);
  const auto pab = kernels::phase_from_phase(f.k.ab, 1.0, 1);
  const auto pbc = kernels::phase_from_phase(f.k.bc, 1.0, 1);
  const auto pca = kernels::phase_from_phase(f.k.ca, 1.0, 1);
  kernels::TauGridSpec octave;
  octave.kind = kernels::TauGridKind::Octave;
  const auto ms = kernels::make_m_list(octave, (pab.n_points() - 1) / 4);
  const auto h = kernels::three_cornered_hat(pab, pbc, pca, ms, 0.683, 1);
  const char* clocks[3] = {"/clocks/A", "/clocks/B", "/clocks/C"};
  const char* pairs[3] = {"/pairs/AB", "/pairs/BC", "/pairs/CA"};
  for (int k = 0; k < 3; ++k) {
    const auto& c = stat_of(r, clocks[k]);
    EXPECT_EQ(c.m, h.clock[k].m);
    EXPECT_EQ(c.dev, h.clock[k].dev) << clocks[k];
    EXPECT_EQ(c.dev_lo, h.clock[k].dev_lo) << clocks[k];
    EXPECT_EQ(c.dev_hi, h.clock[k].dev_hi) << clocks[k];
    EXPECT_EQ(c.edf, h.clock[k].edf) << clocks[k];
    EXPECT_DOUBLE_EQ(c.confidence, 0.683);
    EXPECT_EQ(stat_of(r, pairs[k]).dev, h.pair[k].dev) << pairs[k];
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c.dev[i] > 0.0) {
        EXPECT_LT(c.dev_lo[i], c.dev[i]) << clocks[k] << " m=" << c.m[i];
        EXPECT_GT(c.dev_hi[i], c.dev[i]) << clocks[k] << " m=" << c.m[i];
      }
  }
  EXPECT_NE(r.command_line.find(" hat "), std::string::npos);
  EXPECT_NE(text.find("wrote"), std::string::npos) << text;
}

// `export --format stable32` of a hat's results: each clock's table is titled by the clock and
// the pairs' files, each pair's by its own file, not all by the last pair's file.
TEST(HatCommand, Stable32ExportTitledByClock) {
  const auto f = make_fixture("hat_export", 2000);
  const auto res = f.dir / "hat.h5", all = f.dir / "tables.txt";
  std::string text;
  ASSERT_EQ(run_command(binary() + " hat --taus octave " + f.ab.string() + " " + f.bc.string() +
                            " " + f.ca.string() + " -o " + res.string(),
                        &text),
            0)
      << text;
  ASSERT_EQ(
      run_command(binary() + " export --format stable32 " + res.string() + " -o " + all.string(),
                  &text),
      0)
      << text;
  std::vector<std::string> titles;
  std::ifstream in(all);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("# STATISTICS FOR FILE: ")) titles.push_back(line.substr(23));
  const std::string pairs = " (three-cornered hat of ab.h5, bc.h5, ca.h5)";
  EXPECT_EQ(titles,
            (std::vector<std::string>{"clock A" + pairs, "clock B" + pairs, "clock C" + pairs,
                                      "ab.h5 (pair AB)", "bc.h5 (pair BC)", "ca.h5 (pair CA)"}));
}

TEST(HatCommand, SameFileForOneAndTwoThreads) {
  const auto f = make_fixture("hat_threads", 70000);
  const std::string args =
      " --taus octave " + f.ab.string() + " " + f.bc.string() + " " + f.ca.string() + " -o ";
  std::string text;
  ASSERT_EQ(run_command(binary() + " hat --threads 1" + args + (f.dir / "1.h5").string(), &text), 0)
      << text;
  ASSERT_EQ(run_command(binary() + " hat --threads 2" + args + (f.dir / "2.h5").string(), &text), 0)
      << text;
  const auto one = io::read_results(f.dir / "1.h5"), two = io::read_results(f.dir / "2.h5");
  ASSERT_EQ(one.channels.size(), two.channels.size());
  for (std::size_t i = 0; i < one.channels.size(); ++i) {
    const auto& a = one.channels[i].stats.at(0).second;
    const auto& b = two.channels[i].stats.at(0).second;
    EXPECT_EQ(a.dev, b.dev) << one.channels[i].path;
    EXPECT_EQ(a.dev_lo, b.dev_lo) << one.channels[i].path;
    EXPECT_EQ(a.dev_hi, b.dev_hi) << one.channels[i].path;
  }
}

TEST(CodevCommand, WritesTheSignedCodeviation) {
  const auto f = make_fixture("codev_cli");
  const auto out = f.dir / "codev.h5";
  std::string text;
  ASSERT_EQ(run_command(binary() + " codev --taus octave " + f.ab.string() + " " + f.ca.string() +
                            " -o " + out.string(),
                        &text),
            0)
      << text;
  const auto g = io::read_stat_group(out, "/codev/allan/gcodev");
  EXPECT_THROW(io::read_stat_group(out, "/codev/allan/nope"), io::Error);
  EXPECT_THROW(io::read_stat_group(out, "/nope/allan/gcodev"), io::Error);
  const auto px = kernels::phase_from_phase(f.k.ab, 1.0, 1);
  const auto py = kernels::phase_from_phase(f.k.ca, 1.0, 1);
  kernels::TauGridSpec octave;
  octave.kind = kernels::TauGridKind::Octave;
  const auto c = kernels::gcodev_with_confidence(
      px, py, kernels::make_m_list(octave, (px.n_points() - 1) / 4), 0.683, 1);
  EXPECT_EQ(g.dev, c.codev.dev);
  EXPECT_EQ(g.dev_lo, c.codev.dev_lo);
  EXPECT_EQ(g.dev_hi, c.codev.dev_hi);
  ASSERT_FALSE(g.dev.empty());
  for (std::size_t i = 0; i < g.size(); ++i) {
    // AB and CA share clock A with opposite signs: minus clock A's deviation.
    EXPECT_LT(g.dev[i], 0.0) << "m=" << g.m[i];
    EXPECT_LE(g.dev_lo[i], g.dev[i]);
    EXPECT_GE(g.dev_hi[i], g.dev[i]);
  }
}

TEST(CodevCommand, OfARecordWithItselfIsItsOadev) {
  const auto f = make_fixture("codev_self");
  const auto out = f.dir / "self.h5";
  std::string text;
  ASSERT_EQ(run_command(binary() + " codev " + f.ab.string() + " " + f.ab.string() + " -o " +
                            out.string(),
                        &text),
            0)
      << text;
  const auto g = io::read_stat_group(out, "/codev/allan/gcodev");
  const auto o = io::read_stat_group(out, "/records/x/allan/oadev");
  ASSERT_EQ(g.size(), o.size());
  ASSERT_GT(g.size(), 10u);
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g.n[i], o.n[i]);
    EXPECT_NEAR(g.dev[i] / o.dev[i], 1.0, 1e-12) << "m=" << g.m[i];
    EXPECT_NEAR(g.dev_hi[i] / o.dev_hi[i], 1.0, 1e-9) << "m=" << g.m[i];
  }
}

// Exit status 2, the message naming `what`, and no output file.
void expect_usage_error(const std::string& args, const std::filesystem::path& out,
                        const std::string& what) {
  std::string text;
  EXPECT_EQ(run_command(binary() + " " + args + " -o " + out.string(), &text), 2) << text;
  EXPECT_NE(text.find(what), std::string::npos) << "wanted '" << what << "' in: " << text;
  EXPECT_FALSE(std::filesystem::exists(out)) << args;
}

// hat --clocks A,B,C,D: the six pairs in pair order AB AC AD BC BD CD, each clock as
// n_cornered_hat computes it, the pairs' names and order at the root, the table on stdout with
// the intervals, and the Stable32 export titled by clock and by pair file.
TEST(HatCommand, FourClocksInPairOrder) {
  const std::filesystem::path dir = test::fresh_dir("hat_four");
  const std::size_t n = 3000;
  const std::vector<std::vector<double>> clock = {white(n, 1.0, 21), white(n, 1.5, 22),
                                                  white(n, 2.0, 23), white(n, 2.5, 24)};
  const char* names[6] = {"AB", "AC", "AD", "BC", "BD", "CD"};
  std::vector<kernels::PhaseData> phases;
  std::string inputs;
  std::size_t p = 0;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j, ++p) {
      std::vector<double> d(n);
      for (std::size_t t = 0; t < n; ++t)
        d[t] = clock[i][t] - clock[j][t];
      const auto file = dir / (std::string(names[p]) + ".h5");
      write_phase(file, d);
      inputs += " " + file.string();
      phases.push_back(kernels::phase_from_phase(d, 1.0, 1));
    }
  const auto out = dir / "hat.h5", tables = dir / "tables.txt";
  std::string text;
  ASSERT_EQ(run_command(binary() + " hat --clocks A,B,C,D --taus m:1,4,16" + inputs + " -o " +
                            out.string(),
                        &text),
            0)
      << text;
  EXPECT_NE(text.find("dev D"), std::string::npos) << text;
  EXPECT_NE(text.find("CD = "), std::string::npos) << text;
  const io::RecordingResult r = io::read_results(out);
  ASSERT_EQ(r.channels.size(), 10u);
  const std::vector<std::int64_t> ms = {1, 4, 16};
  const auto h = kernels::n_cornered_hat(phases, 4, ms, 0.683, 1);
  const char* clocks[4] = {"/clocks/A", "/clocks/B", "/clocks/C", "/clocks/D"};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& c = stat_of(r, clocks[k]);
    EXPECT_EQ(c.dev, h.clock[k].dev) << clocks[k];
    EXPECT_EQ(c.dev_lo, h.clock[k].dev_lo) << clocks[k];
    EXPECT_EQ(c.dev_hi, h.clock[k].dev_hi) << clocks[k];
  }
  for (std::size_t q = 0; q < 6; ++q)
    EXPECT_EQ(stat_of(r, std::string("/pairs/") + names[q]).dev, h.pair[q].dev) << names[q];
  ASSERT_EQ(
      run_command(binary() + " export --format stable32 " + out.string() + " -o " + tables.string(),
                  &text),
      0)
      << text;
  std::vector<std::string> titles;
  std::ifstream in(tables);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("# STATISTICS FOR FILE: ")) titles.push_back(line.substr(23));
  ASSERT_EQ(titles.size(), 10u);
  EXPECT_EQ(titles[0], "clock A (4-cornered hat of AB.h5, AC.h5, AD.h5, BC.h5, BD.h5, CD.h5)");
  EXPECT_EQ(titles[9], "CD.h5 (pair CD)");
}

TEST(HatCommand, BadClockListsAreUsageErrors) {
  const auto f = make_fixture("hat_bad_clocks", 200);
  const auto out = f.dir / "out.h5";
  const std::string three = f.ab.string() + " " + f.bc.string() + " " + f.ca.string();
  expect_usage_error("hat --clocks A,B " + three, out, "at least 3 clocks, got 2");
  expect_usage_error("hat --clocks A,B,A " + three, out, "clock 'A' named twice");
  expect_usage_error("hat --clocks A,B/x,C " + three, out, "'B/x' is not a clock name");
  expect_usage_error("hat --clocks A,B,C,D " + three, out,
                     "hat --clocks A,B,C,D needs exactly 6 recordings, got 3");
}

TEST(HatCommand, BadInputsAreUsageErrors) {
  const auto f = make_fixture("hat_bad", 200);
  const auto out = f.dir / "out.h5";
  const std::string ab = f.ab.string(), bc = f.bc.string(), ca = f.ca.string();
  expect_usage_error("codev " + ab, out, "codev needs exactly 2 recordings, got 1 (" + ab + ")");
  expect_usage_error("hat " + ab + " " + bc, out, "hat needs exactly 3 recordings, got 2");
  const auto longer = f.dir / "longer.h5";
  write_phase(longer, white(201, 1.0, 9));
  expect_usage_error("hat " + ab + " " + bc + " " + longer.string(), out,
                     longer.string() + ":/clock/phase: 201 samples where the first record has 200");
  const auto faster = f.dir / "faster.h5";
  write_phase(faster, f.k.ca, 2.0);
  expect_usage_error("codev " + ab + " " + faster.string(), out,
                     faster.string() + ":/clock/phase: sample rate 2");
  const auto shorty = f.dir / "short.h5";
  write_phase(shorty, white(4, 1.0, 10));
  expect_usage_error("codev " + shorty.string() + " " + shorty.string(), out,
                     shorty.string() + ":/clock/phase: 4 samples give 4 phase points, no tau");
  const auto rate = f.dir / "rate.h5";
  write_phase(rate, f.k.ca, 1.0, false, "s", "rate");
  expect_usage_error("hat " + ab + " " + bc + " " + rate.string(), out,
                     rate.string() + ":/clock/phase: data type rate differs from the first "
                                     "record's phase");
  const auto deg = f.dir / "deg.h5";
  write_phase(deg, f.k.ca, 1.0, false, "deg");
  expect_usage_error("codev " + ab + " " + deg.string(), out,
                     deg.string() +
                         ":/clock/phase: units 'deg' differ from the first record's 's'");
  auto gapped = f.k.ca;
  std::fill(gapped.begin(), gapped.end(), std::nan(""));
  const auto empty = f.dir / "allnan.h5";
  write_phase(empty, gapped);
  expect_usage_error("codev " + ab + " " + empty.string(), out, empty.string() + ":/clock/phase: ");
  const auto two = f.dir / "two.h5";
  write_phase(two, f.k.ca, 1.0, true);
  expect_usage_error("hat " + ab + " " + bc + " " + two.string(), out,
                     two.string() + ": several channels");
  expect_usage_error("hat --channel nope " + ab + " " + bc + " " + ca, out,
                     ab + ": no channel 'nope'");
  expect_usage_error("codev " + ab + " " + (f.dir / "missing.h5").string(), out,
                     (f.dir / "missing.h5").string());
  expect_usage_error("codev --taus nonsense " + ab + " " + bc, out, "--taus");
  // The output may not replace an input.
  std::string text;
  const std::string before = test::file_bytes(f.ab);
  EXPECT_EQ(run_command(binary() + " codev " + ab + " " + bc + " -o " + ab, &text), 2) << text;
  EXPECT_EQ(test::file_bytes(f.ab), before);
  // --channel picks one of several in every file.
  EXPECT_EQ(run_command(binary() + " hat --channel phase " + ab + " " + bc + " " + two.string() +
                            " -o " + out.string(),
                        &text),
            0)
      << text;
}

}  // namespace
}  // namespace allanlot
