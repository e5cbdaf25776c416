// Nothing lost on a bad night (docs/reliability.md): each failure an adversarial run found,
// reproduced through the real binary. Outputs never overwrite inputs, OUTDIR is never read as
// input, damaged results files are detected (never trusted by resume, never a crash in a
// reader), a second recording with the same device_id never replaces the first one's results,
// a FIFO never hangs the lot, signals leave a clean OUTDIR with the summary of what is done.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <map>
#include <random>
#include <sys/stat.h>
#include <thread>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

// A lot of `n` simulated six-channel units (`seconds` at 1 kHz) in dir/name.
fs::path make_lot(const fs::path& dir, const std::string& name, int n, int seconds, int seed) {
  std::string out;
  const fs::path lot = dir / name;
  EXPECT_EQ(run_command(binary() + " simulate -q --lot " + std::to_string(n) + " --duration " +
                            std::to_string(seconds) + " --seed " + std::to_string(seed) + " -o " +
                            lot.string(),
                        &out),
            0)
      << out;
  fs::remove(lot / "manifest.txt");
  fs::remove(lot / "lot_model.json");
  return lot;
}

int count_results(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename().string().ends_with(".allan.h5") ? 1 : 0;
  return n;
}

// Runs a command; -1 when it was killed by a signal (a crash), else its exit status.
int run(const std::string& args, std::string* out = nullptr) {
  return run_command("timeout -s KILL 120 " + binary() + " " + args, out);
}

TEST(Night, OutdirInsideTheInputDirectoryIsNeverReadAsInput) {
  const auto dir = test::fresh_dir("night_outdir_inside");
  const fs::path in = make_lot(dir, "in", 2, 10, 3);
  std::string out;
  ASSERT_EQ(run("analyze -q -o " + (in / "results").string() + " " + in.string(), &out), 0) << out;
  const auto first = test::snapshot(in / "results");
  for (int rerun = 0; rerun < 2; ++rerun) {
    EXPECT_EQ(run("analyze -o " + (in / "results").string() + " " + in.string(), &out), 0) << out;
    EXPECT_NE(out.find("2 already up to date"), std::string::npos) << out;
  }
  EXPECT_EQ(count_results(in / "results"), 2);
  for (const auto& [path, bytes] : first) {
    if (!path.string().ends_with(".allan.h5")) continue;
    EXPECT_EQ(test::file_bytes(path), bytes) << path << " was rewritten";
  }
}

// A one-channel recording and its model, for diagnose.
void make_measurement(const fs::path& dir) {
  std::ofstream(dir / "model.json")
      << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.01, "B": 0.001}})";
  std::string out;
  ASSERT_EQ(run("simulate -q --model " + (dir / "model.json").string() +
                    " --duration 300 --seed 4 --channel gyro_z -o " + (dir / "meas.h5").string(),
                &out),
            0)
      << out;
}

TEST(Night, AnOutputThatNamesAnInputIsAUsageErrorAndTheInputIsKept) {
  const auto dir = test::fresh_dir("night_aliases");
  make_measurement(dir);
  std::string out;
  ASSERT_EQ(run("analyze -q -o " + (dir / "out").string() + " " + (dir / "meas.h5").string()), 0);
  const fs::path results = dir / "out" / "meas.allan.h5";
  fs::create_symlink(results, dir / "alias.csv");
  fs::create_hard_link(dir / "meas.h5", dir / "hardlink.json");
  const std::string diag = "diagnose --replicas 4 " + (dir / "meas.h5").string() + " --model " +
                           (dir / "model.json").string();
  const std::vector<std::pair<std::string, fs::path>> cases = {
      {diag + " --model-out " + (dir / "meas.h5").string(), dir / "meas.h5"},
      {diag + " --model-out " + (dir / "hardlink.json").string(), dir / "meas.h5"},
      {diag + " --model-out " + (dir / "model.json").string(), dir / "model.json"},
      {"export " + results.string() + " -o " + results.string(), results},
      {"export " + results.string() + " -o " + (dir / "alias.csv").string(), results},
      {"report " + (dir / "out").string() + " -o " + results.string(), results},
      {"report " + (dir / "out").string() + " -o " + (dir / "out" / "lot_summary.h5").string(),
       dir / "out" / "lot_summary.h5"},
  };
  for (const auto& [args, kept] : cases) {
    const std::string before = test::file_bytes(kept);
    EXPECT_EQ(run(args, &out), 2) << args << "\n" << out;
    EXPECT_NE(out.find(kept.filename().string()), std::string::npos) << args << "\n" << out;
    EXPECT_EQ(test::file_bytes(kept), before) << args << " changed " << kept;
  }
}

// Writes `n` bytes from `rng` at `offset` of the file.
void scribble(const fs::path& p, std::size_t offset, std::size_t n, std::mt19937& rng) {
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(offset));
  for (std::size_t i = 0; i < n; ++i)
    f.put(static_cast<char>(rng() & 0xff));
}

TEST(Night, DamagedResultsNeverCrashAReaderAndAreRedone) {
  const auto dir = test::fresh_dir("night_damaged");
  const fs::path lot = make_lot(dir, "lot", 2, 10, 6);
  const fs::path outdir = dir / "out";
  std::string out;
  ASSERT_EQ(run("analyze -q -o " + outdir.string() + " " + lot.string(), &out), 0) << out;
  const fs::path victim = outdir / "unit_0001.allan.h5";
  const std::string good = test::file_bytes(victim);
  std::mt19937 rng(24);
  // 64 random bytes at offsets spread over the whole file, metadata and data alike.
  for (int trial = 0; trial < 12; ++trial) {
    std::ofstream(victim, std::ios::binary | std::ios::trunc) << good;
    const std::size_t offset = (good.size() - 64) * static_cast<std::size_t>(trial) / 11;
    scribble(victim, offset, 64, rng);
    const std::string label = "64 bytes at " + std::to_string(offset);
    for (const std::string cmd : {"summarize ", "export ", "report "}) {
      const int rc = run(cmd + outdir.string() + (cmd == "export " ? " -o /dev/null" : ""), &out);
      EXPECT_EQ(rc, 1) << cmd << label << "\n" << out;
      EXPECT_NE(out.find("unit_0001.allan.h5"), std::string::npos) << cmd << label << "\n" << out;
    }
    EXPECT_EQ(run("analyze -o " + outdir.string() + " " + lot.string(), &out), 0) << label;
    EXPECT_NE(out.find("analysed 1 of 2"), std::string::npos) << label << "\n" << out;
    EXPECT_EQ(run("export -o /dev/null " + victim.string(), &out), 0) << label << "\n" << out;
  }
}

TEST(Night, ResultsEditedAfterTheyWereWrittenAreRedone) {
  const auto dir = test::fresh_dir("night_edited");
  const fs::path lot = make_lot(dir, "lot", 1, 10, 7);
  const fs::path outdir = dir / "out";
  std::string out;
  ASSERT_EQ(run("analyze -q -o " + outdir.string() + " " + lot.string(), &out), 0) << out;
  const fs::path victim = outdir / "unit_0001.allan.h5";
  {  // a channel group deleted with the HDF5 library: a well-formed file, one channel short
    const hid_t f = H5Fopen(victim.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    EXPECT_GE(H5Ldelete(f, "/imu/gyro_x", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  EXPECT_EQ(run("summarize " + outdir.string(), &out), 1) << out;
  EXPECT_EQ(run("analyze -o " + outdir.string() + " " + lot.string(), &out), 0) << out;
  EXPECT_NE(out.find("analysed 1 of 1"), std::string::npos) << out;
  EXPECT_EQ(run("summarize -q " + outdir.string(), &out), 0) << out;
}

TEST(Night, AnotherRecordingWithTheSameDeviceIdNeverReplacesTheResults) {
  const auto dir = test::fresh_dir("night_same_device");
  const fs::path a = make_lot(dir, "a", 1, 10, 8);
  // b holds unit_0001 too, with other samples, and a unit_0002 that is new.
  const fs::path b = make_lot(dir, "b", 2, 10, 9);
  const fs::path outdir = dir / "out";
  std::string out;
  ASSERT_EQ(run("analyze -q -o " + outdir.string() + " " + a.string(), &out), 0) << out;
  const std::string first = test::file_bytes(outdir / "unit_0001.allan.h5");
  EXPECT_EQ(run("analyze -q -o " + outdir.string() + " " + b.string(), &out), 1) << out;
  EXPECT_NE(out.find((a / "unit_0001.h5").string()), std::string::npos) << out;
  EXPECT_EQ(test::file_bytes(outdir / "unit_0001.allan.h5"), first);
  EXPECT_EQ(count_results(outdir), 2);
}

TEST(Night, AFifoAmongTheInputsFailsAloneWithoutHanging) {
  const auto dir = test::fresh_dir("night_fifo");
  const fs::path lot = make_lot(dir, "lot", 1, 10, 10);
  ASSERT_EQ(::mkfifo((lot / "pipe.h5").c_str(), 0600), 0);
  std::string out;
  EXPECT_EQ(run("analyze -q -o " + (dir / "out").string() + " " + lot.string(), &out), 1) << out;
  EXPECT_NE(out.find("pipe.h5"), std::string::npos) << out;
  EXPECT_NE(out.find("not a regular file"), std::string::npos) << out;
  EXPECT_EQ(count_results(dir / "out"), 1);
  // Named on the command line, it is refused before it is opened (open(2) would block).
  EXPECT_EQ(run("analyze -q -o " + (dir / "out2").string() + " " + (lot / "pipe.h5").string() +
                    " " + (lot / "unit_0001.h5").string(),
                &out),
            1)
      << out;
  EXPECT_NE(out.find("not a regular file"), std::string::npos) << out;
}

TEST(Night, AHugeOmpNumThreadsIsCappedNotACrash) {
  const auto dir = test::fresh_dir("night_omp");
  const fs::path lot = make_lot(dir, "lot", 1, 5, 11);
  std::string out;
  EXPECT_EQ(run_command("OMP_NUM_THREADS=100000 timeout -s KILL 120 " + binary() + " analyze -o " +
                            (dir / "out").string() + " " + lot.string(),
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("OMP_NUM_THREADS"), std::string::npos) << out;
}

// Starts analyze on a lot, waits for the first results file, sends `sig`; returns the exit
// status (128 + signal for a clean stop, as shells report it).
int interrupt_analyze(const fs::path& lot, const fs::path& outdir, int sig) {
  const pid_t pid = test::spawn({binary(), "analyze", "--threads", "1", "--no-progress", "-o",
                                 outdir.string(), lot.string()});
  EXPECT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline &&
         !(fs::exists(outdir) && count_results(outdir) > 0))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, sig);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status) + 1000;
}

TEST(Night, SigtermAndSigintStopCleanlyWithASummaryOfWhatIsDone) {
  const auto dir = test::fresh_dir("night_signals");
  const fs::path lot = make_lot(dir, "lot", 4, 30, 12);
  for (const int sig : {SIGTERM, SIGINT}) {
    const fs::path outdir = dir / ("out" + std::to_string(sig));
    EXPECT_EQ(interrupt_analyze(lot, outdir, sig), 128 + sig);
    int hidden = 0;
    for (const auto& e : fs::directory_iterator(outdir))
      hidden += e.path().filename().string().starts_with(".") ? 1 : 0;
    EXPECT_EQ(hidden, 0) << "temporary files left in " << outdir;
    const int done = count_results(outdir);
    EXPECT_GE(done, 1);
    EXPECT_LT(done, 4);
    EXPECT_TRUE(fs::exists(outdir / "lot_summary.csv"));
    std::string out;
    EXPECT_EQ(run("analyze -o " + outdir.string() + " " + lot.string(), &out), 0) << out;
    EXPECT_EQ(count_results(outdir), 4);
  }
}

TEST(Night, SigtermStopsSimulateAfterTheUnitInFlight) {
  const auto dir = test::fresh_dir("night_simulate_signal");
  const fs::path lot = dir / "lot";
  const pid_t pid = test::spawn({binary(), "simulate", "--lot", "40", "--duration", "60",
                                 "--threads", "1", "-o", lot.string()});
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline && !fs::exists(lot / "unit_0001.h5"))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  for (const auto& e : fs::directory_iterator(lot))
    EXPECT_FALSE(e.path().filename().string().starts_with(".")) << e.path() << " left behind";
}

TEST(Night, StaleTemporaryFilesOfAnEarlierRunAreRemoved) {
  const auto dir = test::fresh_dir("night_stale");
  const fs::path lot = make_lot(dir, "lot", 1, 5, 13);
  const fs::path outdir = dir / "out";
  fs::create_directories(outdir);
  const fs::path stale = outdir / ".unit_0009.allan.h5.tmp.somehost.4242.0";
  const fs::path foreign = outdir / ".notes.txt";
  std::ofstream(stale) << "half a file";
  std::ofstream(foreign) << "not ours";
  fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::hours(2));
  fs::last_write_time(foreign, fs::file_time_type::clock::now() - std::chrono::hours(2));
  std::string out;
  EXPECT_EQ(run("analyze -q -o " + outdir.string() + " " + lot.string(), &out), 0) << out;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(foreign));
}

TEST(Night, SmallerFailuresAreNamed) {
  const auto dir = test::fresh_dir("night_small");
  const fs::path lot = make_lot(dir, "lot", 1, 5, 14);
  std::string out;
  // --confidence nan: a usage error, not a failure of every channel.
  EXPECT_EQ(run("analyze --confidence nan -o " + (dir / "o1").string() + " " + lot.string(), &out),
            2)
      << out;
  EXPECT_NE(out.find("--confidence"), std::string::npos) << out;
  // summarize on an OUTDIR without results: says so, writes nothing.
  fs::create_directories(dir / "empty");
  EXPECT_EQ(run("summarize " + (dir / "empty").string(), &out), 2) << out;
  EXPECT_NE(out.find("no results"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "empty" / "lot_summary.csv"));
  // --seed -1 and 1e23: usage errors, not 2^64 - 1.
  for (const char* seed : {"-1", "1e23"})
    EXPECT_EQ(
        run(std::string("simulate --duration 1 --seed ") + seed + " -o " + (dir / "s.h5").string(),
            &out),
        2)
        << seed << "\n"
        << out;
  // *.H5 in a directory is a recording too.
  fs::create_directories(dir / "upper");
  fs::copy_file(lot / "unit_0001.h5", dir / "upper" / "UNIT.H5");
  EXPECT_EQ(run("analyze -q -o " + (dir / "o2").string() + " " + (dir / "upper").string(), &out), 0)
      << out;
  EXPECT_EQ(count_results(dir / "o2"), 1);
  // A 240-character device_id fits: the temporary name must not exceed 255 bytes.
  {
    test::H5Fixture f(dir / "long.h5");
    f.dataset("/x", std::vector<double>(2000, 1.0), H5T_NATIVE_DOUBLE);
    f.attr("/x", "sample_rate_hz", 100.0);
    f.attr("/", "device_id", std::string(240, 'd'));
  }
  EXPECT_EQ(run("analyze -q -o " + (dir / "o3").string() + " " + (dir / "long.h5").string(), &out),
            0)
      << out;
  // A device_id that is not UTF-8: written as \xNN into the CSV and the HDF5 summary, whose
  // string type says UTF-8, so that spreadsheets and h5py read them.
  {
    test::H5Fixture f(dir / "latin1.h5");
    f.dataset("/x", std::vector<double>(2000, 1.0), H5T_NATIVE_DOUBLE);
    f.attr("/x", "sample_rate_hz", 100.0);
    f.attr("/", "device_id",
           std::string("unit\xE9"
                       "7"));
  }
  EXPECT_EQ(
      run("analyze -q -o " + (dir / "o5").string() + " " + (dir / "latin1.h5").string(), &out), 0)
      << out;
  std::ifstream csv(dir / "o5" / "lot_summary.csv");
  const std::string text((std::istreambuf_iterator<char>(csv)), {});
  EXPECT_NE(text.find("\nunit\\xE97,"), std::string::npos) << text;
  const auto rows = io::read_lot_summary(dir / "o5" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].device_id, "unit\\xE97");
  // A 2-sample channel is a failure with its reason, not "ok" with empty tables.
  {
    test::H5Fixture f(dir / "two.h5");
    f.dataset("/x", {1.0, 2.0}, H5T_NATIVE_DOUBLE);
    f.attr("/x", "sample_rate_hz", 100.0);
  }
  EXPECT_EQ(run("analyze -q -o " + (dir / "o4").string() + " " + (dir / "two.h5").string(), &out),
            2)
      << out;
  EXPECT_NE(out.find("two.h5:/x"), std::string::npos) << out;
}

// A filter that only this test process has (identity, id 40123): the recording it writes is
// what a file compressed with a plugin allanlot's HDF5 lacks looks like to allanlot.
std::size_t identity_filter(unsigned, std::size_t, const unsigned[], std::size_t nbytes,
                            std::size_t*, void**) {
  return nbytes;
}

TEST(Night, AnUnavailableCompressionFilterIsNamed) {
  const auto dir = test::fresh_dir("night_filter");
  const H5Z_class2_t filter{H5Z_CLASS_T_VERS,       40123,   1,       1,
                            "test-identity-filter", nullptr, nullptr, identity_filter};
  ASSERT_GE(H5Zregister(&filter), 0);
  {
    test::H5Fixture f(dir / "plugin.h5");
    f.group("/imu");
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    const hsize_t n = 4000, chunk = 1000;
    H5Pset_chunk(dcpl, 1, &chunk);
    H5Pset_filter(dcpl, 40123, H5Z_FLAG_MANDATORY, 0, nullptr);
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t ds =
        H5Dcreate2(f.id(), "/imu/gyro", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    const std::vector<double> v(n, 1.0);
    ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
    H5Dclose(ds);
    H5Sclose(space);
    H5Pclose(dcpl);
    f.attr("/imu/gyro", "sample_rate_hz", 100.0);
  }
  std::string out;
  EXPECT_EQ(run("analyze -q -o " + (dir / "o").string() + " " + (dir / "plugin.h5").string(), &out),
            2)
      << out;
  EXPECT_NE(out.find("plugin.h5:/imu/gyro: compressed with HDF5 filter 40123 "
                     "(test-identity-filter), which this HDF5 library does not have"),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace allanlot
