// HDF5 metadata read in a child process first (io/isolation.hpp), through the real binary:
// random bytes over a recording's metadata (the global heap that holds its variable-length
// string attributes, where they crashed the HDF5 library in H5HG_read), or over an unsealed
// results file, fail that file by name; the rest of the lot is analysed and summarized, and a
// rerun does the same. `hat`, `codev`, `summarize`, `report` and `export` likewise.
#include "io/recording.hpp"
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::noise;
using test::run_command;

// A unit in the layout of `allanlot simulate`: variable-length string attributes (device_id,
// units, data_type) beside the channels.
void write_unit(const fs::path& path, const std::string& id, unsigned seed) {
  io::RecordingWriter w(path.string(), id, 100.0);
  for (const char* name : {"gyro_x", "gyro_y"}) {
    const std::vector<double> v = noise(2000, seed++);
    w.add_channel({name, "deg/s", v}, {"rate", 0.0});
  }
  w.commit();
}

// `n` random bytes of `seed` at a random place of the first global heap collection ("GCOL")
// of `path`, or of its first 2 KiB when it has none.
void damage_metadata(const fs::path& path, unsigned seed, std::size_t n = 16) {
  std::string bytes = test::file_bytes(path);
  const auto gcol = bytes.find("GCOL");
  std::mt19937 rng(seed);
  const std::size_t start = gcol == std::string::npos ? 0 : gcol + 8;
  const std::size_t span =
      std::min<std::size_t>(gcol == std::string::npos ? 2048 : 256, bytes.size() - start - n);
  const std::size_t at = start + rng() % span;
  for (std::size_t i = 0; i < n; ++i)
    bytes[at + i] = static_cast<char>(rng() & 0xff);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

constexpr unsigned kSeeds = 12;

struct Lot {
  fs::path in, out;
};

// Two good units and kSeeds damaged copies of a third.
Lot damaged_lot(const std::string& name) {
  const fs::path dir = test::fresh_dir(name);
  Lot lot{dir / "in", dir / "out"};
  fs::create_directories(lot.in);
  write_unit(lot.in / "good_a.h5", "good_a", 1);
  write_unit(lot.in / "good_b.h5", "good_b", 3);
  for (unsigned s = 0; s < kSeeds; ++s) {
    const fs::path p = lot.in / ("bad_" + std::to_string(s) + ".h5");
    write_unit(p, "bad_" + std::to_string(s), 5);
    damage_metadata(p, s);
  }
  return lot;
}

// The failed rows of the lot summary, by source file name.
std::set<std::string> failed_files(const fs::path& out) {
  std::set<std::string> failed;
  for (const io::SummaryRow& r : io::read_lot_summary(out / "lot_summary.h5"))
    if (!r.status.is_ok()) failed.insert(fs::path(r.source_file).filename().string());
  return failed;
}

TEST(Isolation, DamagedMetadataFailsItsUnitAndTheLotGoesOn) {
  const Lot lot = damaged_lot("isolation_lot");
  std::string text;
  const std::string cmd = binary() + " analyze -q --no-psd --taus octave -o " + lot.out.string() +
                          " " + lot.in.string();
  const int status = run_command(cmd, &text);
  ASSERT_EQ(status, 1) << text;  // not killed by a signal (-1), and some inputs failed
  ASSERT_TRUE(fs::exists(lot.out / "lot_summary.csv")) << text;
  EXPECT_TRUE(fs::exists(lot.out / "good_a.allan.h5"));
  EXPECT_TRUE(fs::exists(lot.out / "good_b.allan.h5"));
  const std::set<std::string> failed = failed_files(lot.out);
  EXPECT_FALSE(failed.contains("good_a.h5"));
  EXPECT_FALSE(failed.contains("good_b.h5"));
  std::size_t n_bad_failed = 0;
  for (unsigned s = 0; s < kSeeds; ++s) {
    const std::string name = "bad_" + std::to_string(s) + ".h5";
    if (!failed.contains(name)) continue;
    ++n_bad_failed;
    EXPECT_NE(text.find(name), std::string::npos) << name << " is not named:\n" << text;
  }
  EXPECT_GT(n_bad_failed, 0u) << text;
  // The rerun does the same: the good units are current, the damaged ones fail again.
  std::string again;
  EXPECT_EQ(run_command(cmd, &again), 1) << again;
  EXPECT_EQ(failed_files(lot.out), failed);
}

TEST(Isolation, HatAndCodevFailNamingADamagedRecording) {
  const Lot lot = damaged_lot("isolation_paired");
  // The damaged unit the lot fails (its metadata is unreadable, whichever way the library ends).
  std::string text;
  run_command(binary() + " analyze -q --no-psd --no-fit --taus octave -o " + lot.out.string() +
                  " " + lot.in.string(),
              &text);
  const std::set<std::string> failed = failed_files(lot.out);
  ASSERT_FALSE(failed.empty()) << text;
  const std::string bad = (lot.in / *failed.begin()).string();
  const std::string a = (lot.in / "good_a.h5").string(), b = (lot.in / "good_b.h5").string();
  for (const std::string& cmd : {binary() + " hat --channel /imu/gyro_x -o " +
                                     (lot.out / "hat.h5").string() + " " + bad + " " + a + " " + b,
                                 binary() + " codev --channel /imu/gyro_x -o " +
                                     (lot.out / "codev.h5").string() + " " + a + " " + bad}) {
    std::string out;
    EXPECT_EQ(run_command(cmd, &out), 1) << cmd << "\n" << out;
    EXPECT_NE(out.find(bad), std::string::npos) << out;
  }
}

// A results file of an earlier version carries no seal: the same HDF5 image without the
// 512-byte user block that holds the seal (HDF5's addresses are relative to the superblock).
void unseal(const fs::path& path) {
  const std::string bytes = test::file_bytes(path).substr(512);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string unit_name(unsigned s) {
  std::string name = "u";
  name += std::to_string(s);
  return name;
}

TEST(Isolation, DamagedUnsealedResultsAreNamedBySummarizeReportAndExport) {
  const fs::path dir = test::fresh_dir("isolation_results");
  fs::create_directories(dir / "in");
  for (unsigned s = 0; s < 3; ++s)
    write_unit(dir / "in" / (unit_name(s) + ".h5"), unit_name(s), 10 * s);
  std::string text;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-psd --taus octave -o " +
                            (dir / "out").string() + " " + (dir / "in").string(),
                        &text),
            0)
      << text;
  // u0 stays sealed and whole, u1 is unsealed and whole, each copy of u2 unsealed and damaged.
  unseal(dir / "out" / "u1.allan.h5");
  const std::string u2 = test::file_bytes(dir / "out" / "u2.allan.h5");
  ASSERT_EQ(run_command(binary() + " summarize -q " + (dir / "out").string(), &text), 0) << text;
  std::size_t n_unreadable = 0;
  for (unsigned s = 0; s < kSeeds; ++s) {
    std::ofstream(dir / "out" / "u2.allan.h5", std::ios::binary | std::ios::trunc)
        .write(u2.data(), static_cast<std::streamsize>(u2.size()));
    unseal(dir / "out" / "u2.allan.h5");
    damage_metadata(dir / "out" / "u2.allan.h5", s, 64);
    std::string sum, rep, exp;
    const int st_sum = run_command(binary() + " summarize -q " + (dir / "out").string(), &sum);
    const int st_rep = run_command(binary() + " report -q " + (dir / "out").string(), &rep);
    const int st_exp = run_command(binary() + " export -o " + (dir / "table.csv").string() + " " +
                                       (dir / "out").string(),
                                   &exp);
    for (const auto& [st, out] : {std::pair{st_sum, sum}, {st_rep, rep}, {st_exp, exp}}) {
      EXPECT_TRUE(st == 0 || st == 1) << "seed " << s << ": " << out;
      if (st == 1) {
        EXPECT_NE(out.find("u2.allan.h5"), std::string::npos) << out;
      }
    }
    if (st_sum == 1) ++n_unreadable;
    EXPECT_TRUE(fs::exists(dir / "out" / "lot_summary.csv"));
  }
  EXPECT_GT(n_unreadable, 0u);
  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  std::set<std::string> ok_units;
  for (const auto& r : rows)
    if (r.status.is_ok()) ok_units.insert(r.device_id);
  EXPECT_TRUE(ok_units.contains("u0"));
  EXPECT_TRUE(ok_units.contains("u1"));
}

}  // namespace
}  // namespace allanlot
