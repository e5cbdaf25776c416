// Hostile text recordings: gzip bombs and endless lines end at the memory limit with an error
// naming the file and the limit; a value written as a number that is none is an error on the
// first row as further down; RFC 4180 quoting; a NUL in a field is shown, not a cut message;
// a second column named like time stamps is no channel; device ids of other scripts stay apart.
#include "io/error.hpp"
#include "io/recording.hpp"
#include "io/text_fields.hpp"
#include "io/text_recording.hpp"
#include "io/utf8.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

io::InputOptions rate_at(double hz, std::uint64_t memory_limit = 0) {
  io::InputOptions o;
  o.data_type = kernels::DataType::Rate;
  o.sample_rate_hz = hz;
  o.memory_limit = memory_limit;
  return o;
}

// The io::Error's message, or "" when `f` does not throw one.
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const io::Error& e) {
    return e.what();
  }
  return "";
}

// `bytes` of `shell`'s output, gzip-compressed into `path` (a few hundred kB for 64 MiB of
// repeated text: the ratio of a gzip bomb).
void gzip_of(const std::string& shell, std::size_t bytes, const fs::path& path) {
  const std::string cmd =
      "(" + shell + ") | head -c " + std::to_string(bytes) + " | gzip -1 > '" + path.string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ASSERT_LT(fs::file_size(path), bytes / 100);
}

constexpr std::uint64_t kLimit = 1 << 20;
constexpr std::size_t kBomb = std::size_t{64} << 20;

// 64 MiB of "0\n" (32 M samples, 256 MiB as doubles) against a 1 MiB limit; a CSV of three
// columns likewise; 64 MiB without a line end. Each stops at the limit, naming file and limit.
TEST(TextHostile, GzipBombsStopAtTheMemoryLimit) {
  const fs::path dir = test::fresh_dir("text_bomb");
  gzip_of("yes 0", kBomb, dir / "column.txt.gz");
  gzip_of("echo time,gx,gy; yes 0,1,2", kBomb, dir / "rows.csv.gz");
  gzip_of("yes 7 | tr -d '\\n'", kBomb, dir / "line.txt.gz");
  const std::string column = (dir / "column.txt.gz").string();
  std::string e = error_of([&] { io::RecordingReader r(column, rate_at(1.0, kLimit)); });
  EXPECT_NE(e.find(column + ":line 131073: its values need more than the memory limit of 1.0 MiB "
                            "(--memory-limit) allows"),
            std::string::npos)
      << e;
  const std::string rows = (dir / "rows.csv.gz").string();
  e = error_of([&] { io::RecordingReader r(rows, rate_at(1.0, kLimit)); });
  EXPECT_NE(e.find(rows + ":line "), std::string::npos) << e;
  EXPECT_NE(e.find("memory limit of 1.0 MiB (--memory-limit)"), std::string::npos) << e;
  EXPECT_NE(e.find("rows of 3 value(s)"), std::string::npos) << e;
  const std::string line = (dir / "line.txt.gz").string();
  e = error_of([&] { io::RecordingReader r(line, rate_at(1.0, kLimit)); });
  EXPECT_NE(e.find(line + ":line 1: longer than the memory limit of 1.0 MiB (--memory-limit)"),
            std::string::npos)
      << e;
  // Within the limit the same kind of file is read whole.
  gzip_of("yes 0", 100000, dir / "small.txt.gz");
  const io::RecordingReader small((dir / "small.txt.gz").string(), rate_at(1.0, kLimit));
  EXPECT_EQ(small.info().channels.at(0).n_samples, 50000);
}

// A value written as a number that is none (beyond double's range, C's hexadecimal floats) is
// an error naming line and column, on the first row as further down: never a text column
// dropped with a note, never a header that swallows the first sample.
TEST(TextHostile, AMalformedFirstValueIsAnErrorAsFurtherDown) {
  const fs::path dir = test::fresh_dir("text_first_value");
  for (const char* value : {"1e999", "0x1p3"}) {
    const fs::path csv = dir / (std::string("first_") + (value[1] == 'e' ? "big" : "hex") + ".csv");
    std::ofstream(csv) << "time,gx,gy\n0," << value << ",1\n1,2,3\n2,4,5\n";
    std::string e = error_of([&] { io::RecordingReader r(csv.string(), io::InputOptions{}); });
    EXPECT_NE(e.find(csv.string() + ":line 2, column 2 (gx): '" + value + "' is not a number"),
              std::string::npos)
        << e;
    const fs::path single = dir / (csv.stem().string() + ".txt");
    std::ofstream(single) << value << "\n1\n2\n";
    e = error_of([&] { io::RecordingReader r(single.string(), rate_at(1.0)); });
    EXPECT_NE(e.find(single.string() + ":line 1, column 1: '" + value + "' is not a number"),
              std::string::npos)
        << e;
  }
  // A text column stays a text column, with a note.
  std::ofstream(dir / "label.csv") << "time,gx,state\n0,1,ok\n1,2,ok\n2,3,ok\n";
  const io::RecordingReader r((dir / "label.csv").string(), io::InputOptions{});
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_EQ(r.info().notes.at(0), "column 3 (state) is not numeric: not a channel");
}

// RFC 4180: a quoted field may hold the delimiter, and "" inside it is one quote.
TEST(TextHostile, QuotedFieldsKeepTheirDelimiters) {
  std::vector<std::string_view> f;
  io::split_fields(R"(1,"a,b", "c ""d"", e" ,2)", ',', f);
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f[1], "a,b");
  EXPECT_EQ(f[2], R"(c ""d"", e)");
  EXPECT_EQ(io::parse_header_cell(f[2]).name, R"(c "d", e)");
  EXPECT_EQ(io::detect_delimiter(R"("x;y";"1,5")"), ';');
  const fs::path dir = test::fresh_dir("text_quoted");
  std::ofstream(dir / "q.csv") << "time,\"gyro, x [deg/s]\",\"note, free\"\n"
                                  "0,1.5,\"a, b\"\n1,2.5,\"c\"\n2,3.5,\"d, e, f\"\n";
  const io::RecordingReader r((dir / "q.csv").string(), io::InputOptions{});
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_EQ(r.info().channels[0].path, "/gyro, x");
  EXPECT_EQ(r.info().channels[0].units, "deg/s");
  EXPECT_EQ(test::as_vector(r.read(r.info().channels[0])), (std::vector<double>{1.5, 2.5, 3.5}));
}

// A NUL (or an escape sequence) in a field is shown as \xNN: the message goes on after it.
TEST(TextHostile, ANulInAFieldIsShownEscaped) {
  const fs::path dir = test::fresh_dir("text_nul");
  const std::string bad("1\0x\x1b[2J", 7);
  {
    std::ofstream f(dir / "n.csv", std::ios::binary);
    f << "time,gx\n0,1\n1," << bad << "\n2,3\n";
  }
  const std::string e =
      error_of([&] { io::RecordingReader r((dir / "n.csv").string(), io::InputOptions{}); });
  EXPECT_NE(e.find("line 3, column 2 (gx): '1\\x00x\\x1B[2J' is not a number"), std::string::npos)
      << e;
  EXPECT_EQ(e.find('\0'), std::string::npos);
  EXPECT_EQ(io::printable(std::string("a\0\x7f\xff\xc3\xa9", 6)), "a\\x00\\x7F\\xFF\xc3\xa9");
}

// A column named like time stamps beside the time column is no channel (as in an HDF5
// recording), with a note; also when --time-column chose another.
TEST(TextHostile, ASecondTimeColumnIsNoChannel) {
  const fs::path dir = test::fresh_dir("text_two_times");
  std::ofstream(dir / "t.csv") << "time,gx,timestamp_ns\n0,1,100\n1,2,200\n2,3,300\n";
  const io::RecordingReader r((dir / "t.csv").string(), io::InputOptions{});
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_EQ(r.info().channels[0].path, "/gx");
  ASSERT_EQ(r.info().notes.size(), 1u);
  EXPECT_EQ(r.info().notes[0],
            "column 3 (timestamp_ns) is named like time stamps: not a channel (the time is "
            "column 1 (time))");
  io::InputOptions chosen;
  chosen.time_column = "timestamp_ns";
  const io::RecordingReader c((dir / "t.csv").string(), chosen);
  ASSERT_EQ(c.info().channels.size(), 1u);
  EXPECT_EQ(c.info().channels[0].path, "/gx");
  EXPECT_EQ(c.info().channels[0].sample_rate_hz, 1e7);  // 100 ns steps
}

// Names of other scripts keep their letters in the results' file names, so that two units
// in Cyrillic or CJK do not share one; separators, invisible and look-alike characters do not.
TEST(TextHostile, DeviceIdsOfOtherScriptsStayApart) {
  const std::string a = io::sanitize_device_id("датчик");
  const std::string b = io::sanitize_device_id("гироскоп");
  EXPECT_EQ(a, "датчик");
  EXPECT_EQ(b, "гироскоп");
  EXPECT_EQ(io::sanitize_device_id("陀螺仪-7"), "陀螺仪-7");
  EXPECT_EQ(io::sanitize_device_id("ünit é"), "ünit_é");
  // U+202E (right-to-left override), U+200B (zero width space), U+FF0F (fullwidth solidus),
  // U+2215 (division slash), U+00A0 (no-break space), U+3000 (ideographic space), U+FEFF.
  EXPECT_EQ(io::sanitize_device_id("a\u202Eb\u200Bc\uFF0Fd\u2215e\u00A0f\u3000g\uFEFF"),
            "a_b_c_d_e_f_g_");
  EXPECT_EQ(io::sanitize_device_id("\xd0\xb4\xff\xd0"), "д__");  // a cut sequence is bytes
  EXPECT_EQ(io::sanitize_device_id("..\u0434"), "_.д");
}

}  // namespace
}  // namespace allanlot
