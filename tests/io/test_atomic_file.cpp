// io/atomic_file: a device under the final name is written through or refused, never replaced
// (renamed over as root, `export -o /dev/null` had made /dev/null a regular file, and the writes
// of every later test filled /dev).
#include "io/atomic_file.hpp"
#include "io/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, TextToACharacterDeviceIsWrittenThrough) {
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_NO_THROW(io::write_text_atomic("/dev/null", "a,b\n1,2\n"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST(AtomicFile, ADeviceIsNeverReplaced) {
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  // The temporary goes beside the final name, in /dev; where that cannot be created (not root),
  // the write fails earlier, and /dev/null is untouched either way.
  try {
    io::AtomicFile f("/dev/null");
    io::write_text(f, "x");
    EXPECT_THROW(f.commit(), io::Error);
  } catch (const io::Error&) {
  }
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST(AtomicFile, ARegularFileIsReplacedWhole) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "atomic_file";
  fs::create_directories(dir);
  const fs::path p = dir / "out.csv";
  std::ofstream(p) << "old\n";
  io::write_text_atomic(p, "new\n");
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "new");
  EXPECT_TRUE(fs::is_regular_file(p));
}

// A symbolic link planted in OUTDIR under a temporary's name (as a co-user of OUTDIR could, the
// names once being predictable: host, pid and a counter) never redirects the write: the
// temporary's name carries 64 random bits and is created with O_EXCL | O_NOFOLLOW.
TEST(AtomicFile, APlantedLinkNeverRedirectsTheWrite) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "atomic_file_planted";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const fs::path outside = dir / "outside.txt";
  for (int n = 0; n < 16; ++n)
    fs::create_symlink(outside, dir / "out" /
                                    (".report.html.tmp." + io::host_tag() + "." +
                                     std::to_string(::getpid()) + "." + std::to_string(n)));
  io::write_text_atomic(dir / "out" / "report.html", "<html></html>\n");
  EXPECT_FALSE(fs::exists(outside));
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "report.html"));
  EXPECT_FALSE(fs::is_symlink(dir / "out" / "report.html"));
}

TEST(AtomicFile, TemporariesAreCreatedAtOnceUnderUnpredictableNames) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "atomic_file_names";
  fs::remove_all(dir);
  fs::create_directories(dir);
  io::AtomicFile a(dir / "x.csv"), b(dir / "x.csv");
  EXPECT_NE(a.temp_path(), b.temp_path());
  EXPECT_TRUE(fs::is_regular_file(a.temp_path()));  // created by the constructor, exclusively
  const std::string name = a.temp_path().filename().string();
  const std::string tag = name.substr(name.rfind('.') + 1);
  EXPECT_EQ(tag.size(), 16u) << name;
  EXPECT_EQ(tag.find_first_not_of("0123456789abcdef"), std::string::npos) << name;
}

TEST(AtomicFile, ANamedPipeWithoutReaderIsAnErrorNotAWait) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "atomic_file_fifo";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path fifo = dir / "report.html";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    io::write_text_atomic(fifo, "<html></html>\n");
    FAIL() << "written to a pipe nobody reads";
  } catch (const io::Error& e) {
    EXPECT_NE(e.reason().find("named pipe that nobody reads"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
}

}  // namespace
}  // namespace allanlot
