// The lines of a text file, plain or gzip-compressed (io/line_reader.hpp): the same lines from
// both, line endings "\n" and "\r\n" and a last line without one, lines longer than a read
// block kept whole, a line longer than the memory limit and a cut gzip stream refused with the
// file and the line named.
#include "io/line_reader.hpp"

#include "io/error.hpp"
#include "support/h5_fixture.hpp"
#include "support/text_fixture.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::io {
namespace {

namespace fs = std::filesystem;

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::vector<std::string> read_all(const fs::path& path, std::uint64_t max_line = 0) {
  LineReader r(path.string(), max_line);
  std::vector<std::string> lines;
  std::string_view line;
  while (r.next(line)) {
    lines.emplace_back(line);
    EXPECT_EQ(r.line_number(), static_cast<std::int64_t>(lines.size()));
  }
  return lines;
}

// 2.5 MiB: longer than the reader's 1 MiB block, so the line spans two refills.
const std::string kLong(5u << 19, 'x');

TEST(LineReader, PlainAndGzipGiveTheSameLines) {
  const fs::path dir = test::fresh_dir("line_reader_plain_gzip");
  const std::string text = "a,b\nfirst\r\n\n" + kLong + "\nlast without an ending\r";
  write_bytes(dir / "t.csv", text);
  ASSERT_TRUE(test::gzip_copy(dir / "t.csv", dir / "t.csv.gz"));
  const std::vector<std::string> want = {"a,b", "first", "", kLong, "last without an ending"};
  EXPECT_EQ(read_all(dir / "t.csv"), want);
  EXPECT_EQ(read_all(dir / "t.csv.gz"), want);
  EXPECT_FALSE(is_gzip_file((dir / "t.csv").string()));
  EXPECT_TRUE(is_gzip_file((dir / "t.csv.gz").string()));
  // The hint is the text's size for both: gzip's trailer records it.
  EXPECT_EQ(text_size_hint((dir / "t.csv").string()), text.size());
  EXPECT_EQ(text_size_hint((dir / "t.csv.gz").string()), text.size());

  LineReader r((dir / "t.csv.gz").string());
  std::string_view line;
  while (r.next(line)) {
  }
  EXPECT_EQ(r.bytes(), text.size());  // every byte after decompression, line endings included
  EXPECT_FALSE(r.next(line));         // and the end stays the end
}

TEST(LineReader, ALineLongerThanTheLimitIsAnErrorNamingIt) {
  const fs::path dir = test::fresh_dir("line_reader_limit");
  write_bytes(dir / "bomb.txt", "header\n" + kLong);
  try {
    read_all(dir / "bomb.txt", 4096);
    FAIL() << "a 2.5 MiB line was read with a limit of 4096 bytes";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bomb.txt"), std::string::npos) << what;
    EXPECT_NE(what.find("line 2"), std::string::npos) << what;
    EXPECT_NE(what.find("memory limit"), std::string::npos) << what;
  }
  EXPECT_EQ(read_all(dir / "bomb.txt", kLong.size() + 1).back(), kLong);  // within it: read
}

TEST(LineReader, ACutGzipStreamAndAMissingFileAreErrors) {
  const fs::path dir = test::fresh_dir("line_reader_cut");
  std::string text;
  for (int i = 0; i < 20000; ++i)
    text += std::to_string(i * 7919 % 100003) + "\n";
  write_bytes(dir / "t.txt", text);
  ASSERT_TRUE(test::gzip_copy(dir / "t.txt", dir / "t.txt.gz"));
  const auto size = fs::file_size(dir / "t.txt.gz");
  fs::resize_file(dir / "t.txt.gz", size / 2);
  try {
    read_all(dir / "t.txt.gz");
    FAIL() << "half a gzip stream was read to its end";
  } catch (const Error& e) {
    // zlib reports the end of a cut stream as Z_BUF_ERROR after the last whole block.
    EXPECT_EQ(e.file(), (dir / "t.txt.gz").string());
    EXPECT_NE(e.dataset().find("line "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated or corrupt"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LineReader((dir / "absent.txt").string()), Error);
  EXPECT_EQ(memory_text(std::uint64_t{3} << 19), "1.5 MiB");
}

}  // namespace
}  // namespace allanlot::io
