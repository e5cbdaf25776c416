// io/atomic_file: a device under the final name is written through or refused, never replaced
// (renamed over as root, `export -o /dev/null` had made /dev/null a regular file, and the writes
// of every later test filled /dev).
#include "io/atomic_file.hpp"
#include "io/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

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

}  // namespace
}  // namespace allanlot
