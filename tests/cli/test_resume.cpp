// Lots at scale: resume (complete and current results are skipped, anything else redone), the
// memory budget (waves of channels give the same numbers), and SIGKILL at random moments of
// a lot run (only complete results files are ever left; the rerun completes the lot).
#include "io/fingerprint.hpp"
#include "io/recording.hpp"
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

// A small lot: `n` six-channel units of 60 s at 1 kHz (the embedded demo model).
fs::path make_lot(const fs::path& dir, int n, int seed = 1) {
  std::string out;
  const fs::path lot = dir / "lot";
  EXPECT_EQ(test::run_command(test::binary() + " simulate --lot " + std::to_string(n) +
                                  " --duration 60 --seed " + std::to_string(seed) + " -o " +
                                  lot.string(),
                              &out),
            0)
      << out;
  return lot;
}

struct Stamp {
  ino_t inode = 0;
  std::int64_t mtime_ns = 0;
  bool operator==(const Stamp&) const = default;
};

std::map<std::string, Stamp> results_stamps(const fs::path& outdir) {
  std::map<std::string, Stamp> m;
  for (const auto& e : fs::directory_iterator(outdir)) {
    const std::string name = e.path().filename().string();
    if (!name.ends_with(".allan.h5")) continue;
    struct stat st {};
    ::stat(e.path().c_str(), &st);
    m[name] = {st.st_ino, st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec};
  }
  return m;
}

std::string analyze(const fs::path& outdir, const std::string& inputs, const std::string& extra,
                    int* status) {
  std::string out;
  *status = test::run_command(test::binary() + " analyze --stats oadev --no-progress " + extra +
                                  " -o " + outdir.string() + " " + inputs,
                              &out);
  return out;
}

TEST(Resume, SkipsCurrentResultsAndRedoesChangedOnes) {
  const fs::path dir = test::fresh_dir("resume");
  const fs::path lot = make_lot(dir, 3);
  const fs::path out = dir / "out";
  int st = 0;
  std::string text = analyze(out, lot.string(), "", &st);
  ASSERT_EQ(st, 0) << text;
  const auto first = results_stamps(out);
  ASSERT_EQ(first.size(), 3u);

  // The same command: nothing is rewritten.
  text = analyze(out, lot.string(), "", &st);
  EXPECT_EQ(st, 0) << text;
  EXPECT_NE(text.find("3 already up to date"), std::string::npos) << text;
  EXPECT_EQ(results_stamps(out), first);

  // A touched input (same bytes, new time): the content hash decides that it is current.
  fs::last_write_time(lot / "unit_0002.h5", fs::file_time_type::clock::now());
  text = analyze(out, lot.string(), "", &st);
  EXPECT_NE(text.find("3 already up to date"), std::string::npos) << text;
  EXPECT_EQ(results_stamps(out), first);

  // Other content under the same name (another seed's unit 3): redone; the others are not.
  const fs::path other = make_lot(dir / "other", 3, 77);
  fs::copy_file(other / "unit_0003.h5", lot / "unit_0003.h5", fs::copy_options::overwrite_existing);
  text = analyze(out, lot.string(), "", &st);
  EXPECT_NE(text.find("2 already up to date"), std::string::npos) << text;
  auto now = results_stamps(out);
  EXPECT_EQ(now["unit_0001.allan.h5"], first.at("unit_0001.allan.h5"));
  EXPECT_EQ(now["unit_0002.allan.h5"], first.at("unit_0002.allan.h5"));
  EXPECT_NE(now["unit_0003.allan.h5"], first.at("unit_0003.allan.h5"));

  // Other options change the results: everything is redone; so does --force.
  const auto before = results_stamps(out);
  text = analyze(out, lot.string(), "--taus octave", &st);
  EXPECT_EQ(text.find("up to date"), std::string::npos) << text;
  for (const auto& [name, s] : results_stamps(out))
    EXPECT_NE(s, before.at(name)) << name;
  const auto octave = results_stamps(out);
  text = analyze(out, lot.string(), "--taus octave --force", &st);
  for (const auto& [name, s] : results_stamps(out))
    EXPECT_NE(s, octave.at(name)) << name;

  // A damaged results file is not current: redone.
  {
    std::ofstream damage(out / "unit_0001.allan.h5", std::ios::trunc);
    damage << "not hdf5";
  }
  text = analyze(out, lot.string(), "--taus octave", &st);
  EXPECT_EQ(st, 0) << text;
  EXPECT_NE(text.find("2 already up to date"), std::string::npos) << text;
  EXPECT_NO_THROW(io::read_results(out / "unit_0001.allan.h5"));

  // The default gap policy spelled out is the same stamp; another policy is another: redone.
  text = analyze(out, lot.string(), "--taus octave --gaps fill:10", &st);
  EXPECT_NE(text.find("3 already up to date"), std::string::npos) << text;
  text = analyze(out, lot.string(), "--taus octave --gaps skip", &st);
  EXPECT_EQ(st, 0) << text;
  EXPECT_EQ(text.find("up to date"), std::string::npos) << text;
}

TEST(MemoryLimit, WavesOfOneChannelGiveTheSameNumbers) {
  const fs::path dir = test::fresh_dir("memory_limit");
  const fs::path lot = make_lot(dir, 1);
  int st = 0;
  std::string text = analyze(dir / "a", (lot / "unit_0001.h5").string(), "", &st);
  ASSERT_EQ(st, 0) << text;
  // A limit that holds one 60 s channel at 1 kHz (60 000 samples, 32 bytes a sample in flight,
  // 1.9 MB) but not two: one channel per wave, on two threads.
  text = analyze(dir / "b", (lot / "unit_0001.h5").string(), "--threads 2 --memory-limit 2500K -v",
                 &st);
  ASSERT_EQ(st, 0) << text;
  EXPECT_NE(text.find("peak memory"), std::string::npos) << text;
  const auto a = io::read_results(dir / "a" / "unit_0001.allan.h5");
  const auto b = io::read_results(dir / "b" / "unit_0001.allan.h5");
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (std::size_t i = 0; i < a.channels.size(); ++i) {
    ASSERT_EQ(a.channels[i].stats.size(), b.channels[i].stats.size());
    for (std::size_t k = 0; k < a.channels[i].stats.size(); ++k)
      EXPECT_EQ(a.channels[i].stats[k].second.dev, b.channels[i].stats[k].second.dev);
    ASSERT_TRUE(a.channels[i].fit && b.channels[i].fit);
    for (std::size_t t = 0; t < a.channels[i].fit->terms.size(); ++t)
      EXPECT_EQ(a.channels[i].fit->terms[t].value, b.channels[i].fit->terms[t].value);
  }
  // A limit below one channel's need: every channel fails, unread, naming the need and the
  // limit; nothing could be analysed (status 2).
  text = analyze(dir / "d", (lot / "unit_0001.h5").string(), "--memory-limit 1M", &st);
  EXPECT_EQ(st, 2) << text;
  EXPECT_NE(text.find(":/imu/gyro_x: 60000 samples need about 1.83 MiB to analyse (32 bytes a "
                      "sample), more than the memory limit of 1 MiB (--memory-limit"),
            std::string::npos)
      << text;
  for (const char* bad : {"0", "-5G", "12X", "150%", "lots"}) {
    std::string out;
    EXPECT_EQ(test::run_command(test::binary() + " analyze --memory-limit " + bad + " -o " +
                                    (dir / "c").string() + " " + lot.string(),
                                &out),
              2)
        << bad << ": " << out;
  }
}

// The input hash of the stamp: each channel's digest, chained in channel order (the channels
// are read and hashed by whichever thread takes them), the same for any thread count; and a
// digest that moves with any change of a sample's value or place, of the length or the path.
TEST(InputHash, ChannelDigestsChainedInOrderForAnyThreadCount) {
  const fs::path dir = test::fresh_dir("input_hash");
  const fs::path unit = make_lot(dir, 1) / "unit_0001.h5";
  std::string hash[2];
  for (const int threads : {1, 2}) {
    int st = 0;
    const fs::path out = dir / ("t" + std::to_string(threads));
    const std::string text =
        analyze(out, unit.string(), "--threads " + std::to_string(threads), &st);
    ASSERT_EQ(st, 0) << text;
    const auto stamp = io::read_results_stamp(out / "unit_0001.allan.h5");
    ASSERT_TRUE(stamp.has_value());
    hash[threads - 1] = stamp->input_hash;
  }
  EXPECT_EQ(hash[0], hash[1]);
  io::RecordingReader reader(unit.string());
  std::uint64_t chained = io::kHashSeed;
  for (const io::ChannelInfo& ch : reader.info().channels)
    chained = io::combine_hash(chained, io::channel_digest(ch.path, reader.read(ch)));
  EXPECT_EQ(hash[0], io::hash_hex(chained));

  std::vector<double> x(1003);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = std::sin(0.1 * static_cast<double>(i));
  const std::uint64_t d = io::channel_digest("/imu/gyro_x", x);
  std::set<std::uint64_t> seen{d};
  auto changed = x;
  changed[1001] = std::nextafter(changed[1001], 2.0);  // in the tail after the last eight
  seen.insert(io::channel_digest("/imu/gyro_x", changed));
  changed = x;
  std::swap(changed[0], changed[1]);  // two chains exchange their first words
  seen.insert(io::channel_digest("/imu/gyro_x", changed));
  changed = x;
  std::swap(changed[0], changed[8]);  // the same chain, two words in another order
  seen.insert(io::channel_digest("/imu/gyro_x", changed));
  seen.insert(io::channel_digest("/imu/gyro_y", x));
  seen.insert(io::channel_digest("/imu/gyro_x", std::span<const double>(x).first(1002)));
  EXPECT_EQ(seen.size(), 6u);
  EXPECT_NE(io::combine_hash(io::combine_hash(io::kHashSeed, 1), 2),
            io::combine_hash(io::combine_hash(io::kHashSeed, 2), 1));
}

// Every visible results file must be complete (it reads back, with every channel); temporary
// files are hidden, and a killed run may leave one behind, never under a results name.
void expect_only_complete_results(const fs::path& outdir, int* n_complete) {
  *n_complete = 0;
  for (const auto& e : fs::directory_iterator(outdir)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".")) continue;
    if (name.ends_with(".allan.h5")) {
      io::RecordingResult r;
      ASSERT_NO_THROW(r = io::read_results(e.path())) << name;
      EXPECT_EQ(r.channels.size(), 6u) << name;
      ++*n_complete;
    } else {
      EXPECT_TRUE(name == "lot_summary.csv" || name == "lot_summary.h5" ||
                  name == "lot_statistics.csv")
          << name;
    }
  }
  if (fs::exists(outdir / "lot_summary.h5")) {
    EXPECT_NO_THROW(io::read_lot_summary(outdir / "lot_summary.h5"));
  }
}

TEST(Sigkill, KilledAtRandomMomentsLeavesOnlyCompleteResultsAndTheRerunCompletes) {
  const fs::path dir = test::fresh_dir("sigkill");
  const int n_units = 6;
  const fs::path lot = make_lot(dir, n_units);
  const fs::path out = dir / "out";
  // Kill times spread over a run (about 0.3-1 s per unit here, more under ASan); a fixed
  // pseudo-random sequence so that a failure can be replayed.
  std::uint32_t s = 12345;
  int kills = 0;
  for (int round = 0; round < 8; ++round) {
    s = s * 1664525u + 1013904223u;
    const int delay_ms = 50 + static_cast<int>(s % 1500);
    const pid_t pid = test::spawn({test::binary(), "analyze", "--stats", "oadev", "--threads", "1",
                                   "-o", out.string(), lot.string()});
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    kills += WIFSIGNALED(status) ? 1 : 0;
    if (!fs::exists(out)) continue;
    int n = 0;
    expect_only_complete_results(out, &n);
  }
  EXPECT_GT(kills, 0);
  int st = 0;
  const std::string text = analyze(out, lot.string(), "", &st);
  EXPECT_EQ(st, 0) << text;
  int n = 0;
  expect_only_complete_results(out, &n);
  EXPECT_EQ(n, n_units);
  EXPECT_EQ(io::read_lot_summary(out / "lot_summary.h5").size(), 6u * n_units);
}

}  // namespace
}  // namespace allanlot
