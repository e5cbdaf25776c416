// Faults around a lot run: an output directory that cannot hold results, a disk
// that fills up in the middle of a write (a real, small tmpfs), and two `analyze` processes
// writing into the same OUTDIR at once. In every case: never a corrupt or half-written results
// file under its final name, a lot summary consistent with the results files present, and a
// rerun that completes the lot. SIGKILL at random moments is tests/cli/test_resume.cpp's.
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

constexpr int kChannels = 6;  // the embedded demo unit

// A lot of `n` six-channel units of `seconds` at 1 kHz (the embedded demo model).
fs::path make_lot(const fs::path& dir, int n, int seconds = 20) {
  std::string out;
  const fs::path lot = dir / "lot";
  EXPECT_EQ(run_command(binary() + " simulate -q --lot " + std::to_string(n) + " --duration " +
                            std::to_string(seconds) + " --seed 5 -o " + lot.string(),
                        &out),
            0)
      << out;
  return lot;
}

// Checks the invariants of an OUTDIR after any run, finished, failed or killed: every visible
// results file reads back complete, no temporary file is left under a visible name, and when a
// lot summary exists, its ok rows are exactly the channels of the results files present.
// Returns the device ids of the complete results files.
std::set<std::string> check_outdir(const fs::path& outdir) {
  std::set<std::string> devices;
  if (!fs::exists(outdir)) return devices;
  for (const auto& e : fs::directory_iterator(outdir)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".")) continue;
    if (name.ends_with(".allan.h5")) {
      io::RecordingResult r;
      EXPECT_NO_THROW(r = io::read_results(e.path())) << name;
      EXPECT_EQ(r.channels.size(), static_cast<std::size_t>(kChannels)) << name;
      for (const auto& ch : r.channels)
        EXPECT_EQ(io::to_string(ch.status), "ok") << name << ch.path;
      devices.insert(r.device_id);
    } else {
      EXPECT_TRUE(name == "lot_summary.csv" || name == "lot_summary.h5" ||
                  name == "lot_statistics.csv")
          << name;
    }
  }
  if (fs::exists(outdir / "lot_summary.h5")) {
    std::vector<io::SummaryRow> rows;
    EXPECT_NO_THROW(rows = io::read_lot_summary(outdir / "lot_summary.h5"));
    std::map<std::string, int> ok_rows;
    for (const auto& r : rows)
      if (io::to_string(r.status) == "ok") ++ok_rows[r.device_id];
    for (const auto& [device, n] : ok_rows) {
      EXPECT_TRUE(devices.count(device)) << device << " is in the summary without results";
      EXPECT_EQ(n, kChannels) << device;
    }
  }
  return devices;
}

// Hidden files left in OUTDIR (temporaries of an interrupted write).
int hidden_files(const fs::path& outdir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(outdir))
    n += e.path().filename().string().starts_with(".") ? 1 : 0;
  return n;
}

// A tmpfs mounted for the test and unmounted at its end; mounted() is false where this
// process may not mount (not root, no CAP_SYS_ADMIN), and the test then skips.
class Tmpfs {
public:
  Tmpfs(const fs::path& dir, const std::string& options) : dir_(dir) {
    fs::create_directories(dir);
    mounted_ = run_command("mount -t tmpfs -o " + options + " allanlot-test " + dir.string()) == 0;
  }
  ~Tmpfs() {
    if (mounted_) run_command("umount " + dir_.string());
  }
  Tmpfs(const Tmpfs&) = delete;
  Tmpfs& operator=(const Tmpfs&) = delete;
  bool mounted() const { return mounted_; }
  bool remount(const std::string& options) {
    return run_command("mount -o remount," + options + " " + dir_.string()) == 0;
  }

private:
  fs::path dir_;
  bool mounted_ = false;
};

// fresh_dir, after unmounting what an earlier, interrupted run of this test left mounted.
fs::path fresh_test_dir(const std::string& name) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / name;
  run_command("umount -q " + (dir / "mnt").string());
  return test::fresh_dir(name);
}

TEST(Faults, OutputDirectoryThatCannotHoldResultsIsAUsageError) {
  const fs::path dir = fresh_test_dir("faults_outdir");
  const fs::path lot = make_lot(dir, 1, 5);
  const auto inputs = test::snapshot(lot);
  { std::ofstream(dir / "a_file") << "x"; }
  std::string text;
  // A regular file, a path below a regular file, and a directory that cannot be created.
  for (const fs::path& bad : {dir / "a_file", dir / "a_file" / "sub", fs::path("/proc/allanlot")}) {
    EXPECT_EQ(run_command(binary() + " analyze -q -o " + bad.string() + " " + lot.string(), &text),
              2)
        << bad;
    EXPECT_NE(text.find("allanlot: error: "), std::string::npos) << text;
    EXPECT_NE(text.find(bad.string()), std::string::npos) << text;
  }
  EXPECT_EQ(test::file_bytes(dir / "a_file"), "x");
  // A directory that exists but is not writable: a read-only file system, since root (CI)
  // ignores permission bits.
  Tmpfs ro(dir / "mnt", "ro,size=1m");
  if (ro.mounted()) {
    EXPECT_EQ(
        run_command(binary() + " analyze -q -o " + (dir / "mnt").string() + " " + lot.string(),
                    &text),
        2);
    EXPECT_NE(text.find((dir / "mnt").string() + " is not writable"), std::string::npos) << text;
    EXPECT_EQ(run_command(binary() + " analyze -q -o " + (dir / "mnt" / "sub").string() + " " +
                              lot.string(),
                          &text),
              2);
    EXPECT_NE(text.find("cannot create output directory"), std::string::npos) << text;
  }
  EXPECT_EQ(test::snapshot(lot), inputs);
  if (!ro.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here: read-only case not run";
}

// Disk full: OUTDIR on a tmpfs too small for the lot, at sizes where the space runs out in the
// first results file, in the middle of the lot and at the lot summary. Every run must fail
// with a message naming the file it could not write, leave only complete results files and no
// temporary, and the rerun on a larger disk must complete the lot.
TEST(Faults, DiskFullNeverLeavesAHalfWrittenFileAndTheRerunCompletes) {
  const fs::path dir = fresh_test_dir("faults_disk_full");
  const int n_units = 4;
  const fs::path lot = make_lot(dir, n_units);
  const auto inputs = test::snapshot(lot);
  // How large one unit's results are, measured on a real disk.
  std::string text;
  ASSERT_EQ(run_command(binary() + " analyze -q -o " + (dir / "ref").string() + " " +
                            (lot / "unit_0001.h5").string(),
                        &text),
            0)
      << text;
  const auto unit_bytes = fs::file_size(dir / "ref" / "unit_0001.allan.h5");
  const fs::path mnt = dir / "mnt";
  int faults = 0;
  // Sizes in units of one results file: the first write fails, one unit fits, most of the lot
  // fits; tmpfs rounds its size to pages.
  for (const double fraction : {0.5, 1.5, 3.2, 4.05}) {
    SCOPED_TRACE(fraction);
    const auto size = static_cast<std::uintmax_t>(fraction * static_cast<double>(unit_bytes));
    Tmpfs disk(mnt, "size=" + std::to_string(size));
    if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
    const fs::path out = mnt / "out";
    const int rc =
        run_command(binary() + " analyze -q -o " + out.string() + " " + lot.string(), &text);
    EXPECT_NE(rc, 0) << text;
    faults += rc != 0 ? 1 : 0;
    // The message names the file that could not be written and the system's reason.
    bool named = false;
    for (std::size_t at = text.find("allanlot: error: "); at != std::string::npos;
         at = text.find("allanlot: error: ", at + 1)) {
      const std::string line = text.substr(at, text.find('\n', at) - at);
      named = named || (line.find(out.string() + "/") != std::string::npos &&
                        line.find("No space left on device") != std::string::npos);
    }
    EXPECT_TRUE(named) << text;
    check_outdir(out);
    EXPECT_EQ(hidden_files(out), 0);
    // The rerun, with room: the lot completes, and what was complete is kept.
    ASSERT_TRUE(disk.remount("size=64m"));
    const int rerun =
        run_command(binary() + " analyze -q -o " + out.string() + " " + lot.string(), &text);
    EXPECT_EQ(rerun, 0) << text;
    EXPECT_EQ(check_outdir(out).size(), static_cast<std::size_t>(n_units));
    EXPECT_EQ(io::read_lot_summary(out / "lot_summary.h5").size(),
              static_cast<std::size_t>(n_units * kChannels));
  }
  EXPECT_EQ(faults, 4);
  EXPECT_EQ(test::snapshot(lot), inputs);
}

// summarize on a disk with room for the two CSV files but not for lot_summary.h5: the
// summary of the earlier run stays whole (its CSV and HDF5 files agree), none half replaced.
TEST(Faults, ASummaryThatCannotBeWrittenWholeLeavesTheEarlierOne) {
  const fs::path dir = fresh_test_dir("faults_summary_pair");
  const fs::path lot = make_lot(dir, 3, 5);
  const fs::path mnt = dir / "mnt";
  Tmpfs disk(mnt, "size=4m");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
  const fs::path out = mnt / "out";
  std::string text;
  ASSERT_EQ(
      run_command(binary() + " analyze -q --no-psd -o " + out.string() + " " + lot.string(), &text),
      0)
      << text;
  // One unit's results go: the next summary has other rows than the one on disk.
  fs::remove(out / "unit_0002.allan.h5");
  const auto before = test::snapshot(out);
  const auto csv_blocks = (fs::file_size(out / "lot_summary.csv") + 4095) / 4096 +
                          (fs::file_size(out / "lot_statistics.csv") + 4095) / 4096;
  ASSERT_GT(fs::file_size(out / "lot_summary.h5"), 3 * 4096u);
  run_command("dd if=/dev/zero of=" + (mnt / "fill").string() + " bs=4k count=" +
              std::to_string(fs::space(mnt).available / 4096 - csv_blocks) + " 2>/dev/null");
  EXPECT_EQ(run_command(binary() + " summarize " + out.string(), &text), 2) << text;
  EXPECT_NE(text.find("No space left on device"), std::string::npos) << text;
  EXPECT_TRUE(test::snapshot(out) == before) << "a summary file of " << out << " changed";
  EXPECT_EQ(hidden_files(out), 0);
}

int wait_status(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Two processes analyse overlapping halves of a lot into one OUTDIR at the same time, then
// both the whole lot with --force (every file written twice, concurrently). Both must succeed,
// every results file must be complete, the summary must list exactly the units present, and a
// rerun must find everything up to date.
TEST(Faults, TwoRunsIntoTheSameOutdirAtOnce) {
  const fs::path dir = fresh_test_dir("faults_concurrent");
  const int n_units = 6;
  const fs::path lot = make_lot(dir, n_units, 10);
  const fs::path out = dir / "out";
  auto units = [&](int from, int to) {
    std::vector<std::string> a{binary(), "analyze", "-q", "--threads", "1", "-o", out.string()};
    for (int u = from; u <= to; ++u) {
      char name[32];
      std::snprintf(name, sizeof name, "unit_%04d.h5", u);
      a.push_back((lot / name).string());
    }
    return a;
  };
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE(round);
    auto a = round == 0 ? units(1, 4) : units(1, n_units);
    auto b = round == 0 ? units(3, n_units) : units(1, n_units);
    if (round > 0) {
      a.push_back("--force");
      b.push_back("--force");
    }
    const pid_t pa = test::spawn(a), pb = test::spawn(b);
    ASSERT_GT(pa, 0);
    ASSERT_GT(pb, 0);
    EXPECT_EQ(wait_status(pa), 0);
    EXPECT_EQ(wait_status(pb), 0);
    EXPECT_EQ(check_outdir(out).size(), static_cast<std::size_t>(n_units));
    EXPECT_EQ(io::read_lot_summary(out / "lot_summary.h5").size(),
              static_cast<std::size_t>(n_units * kChannels));
    EXPECT_EQ(hidden_files(out), 0);
  }
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -o " + out.string() + " " + lot.string(), &text), 0)
      << text;
  EXPECT_NE(text.find(std::to_string(n_units) + " already up to date"), std::string::npos) << text;
}

// A full disk while simulate writes a recording or diagnose writes its -o file: a clean
// error naming the file and no file left, never a crash (HDF5
// left to flush the file that could not be written would crash at exit).
TEST(Faults, DiskFullInSimulateAndDiagnoseIsACleanError) {
  const fs::path dir = fresh_test_dir("faults_disk_full_writers");
  std::string text;
  std::ofstream(dir / "model.json")
      << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.01}})";
  ASSERT_EQ(run_command(binary() + " simulate -q --model " + (dir / "model.json").string() +
                            " --duration 200 --channel gyro_z -o " + (dir / "meas.h5").string(),
                        &text),
            0)
      << text;
  const fs::path mnt = dir / "mnt";
  const Tmpfs disk(mnt, "size=1m");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
  EXPECT_EQ(run_command(binary() + " simulate --duration 600 -o " + (mnt / "u.h5").string(), &text),
            2)
      << text;
  EXPECT_NE(text.find("No space left on device"), std::string::npos) << text;
  // A results file on that disk, for diagnose -o to add its group to.
  ASSERT_EQ(run_command(binary() + " analyze -q --no-psd -o " + (mnt / "res").string() + " " +
                            (dir / "meas.h5").string(),
                        &text),
            0)
      << text;
  const auto results = test::snapshot(mnt / "res");
  // Fill the disk (dd stops when it is full), then ask diagnose for a new -o file there.
  const fs::path fill = mnt / "fill";
  run_command("dd if=/dev/zero of=" + fill.string() + " bs=4k count=1000 2>/dev/null");
  const std::string diagnose = binary() + " diagnose --replicas 2 " + (dir / "meas.h5").string() +
                               " --model " + (dir / "model.json").string() + " -o ";
  EXPECT_EQ(run_command(diagnose + (mnt / "d.h5").string() + " > /dev/null", &text), 1) << text;
  // Leave room for a copy of the results file and a block, not for the diagnosis group, and
  // ask diagnose to add its group to the results file: a clean error (not a crash of HDF5 at
  // exit), the file as it was.
  fs::remove(fill);
  const auto room = fs::file_size(mnt / "res" / "meas.allan.h5") / 4096 + 2;
  run_command("dd if=/dev/zero of=" + fill.string() + " bs=4k count=" +
              std::to_string(fs::space(mnt).available / 4096 - room) + " 2>/dev/null");
  EXPECT_EQ(run_command(diagnose + (mnt / "res" / "meas.allan.h5").string(), &text), 1) << text;
  EXPECT_NE(text.find("No space left on device"), std::string::npos) << text;
  EXPECT_EQ(test::snapshot(mnt / "res"), results);
  for (const auto& e : fs::directory_iterator(mnt))
    EXPECT_TRUE(e.path().filename() == "fill" || e.path().filename() == "res")
        << e.path() << " left on the full disk";
}

}  // namespace
}  // namespace allanlot
