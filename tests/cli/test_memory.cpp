// The memory limit's text (src/workflow/memory.hpp, analyze --memory-limit): binary units in
// any case, a plain byte count, a share of the machine's memory; anything else an error
// quoting the text.
#include "src/workflow/memory.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace allanlot::workflow {
namespace {

constexpr std::uint64_t kMiB = 1024ull * 1024;
constexpr std::uint64_t kGiB = 1024ull * kMiB;

TEST(MemorySize, UnitsAreBinaryAndTheirCaseFree) {
  EXPECT_EQ(parse_memory_size("2000000000"), 2000000000ull);
  EXPECT_EQ(parse_memory_size("64B"), 64ull);
  EXPECT_EQ(parse_memory_size("1k"), 1024ull);
  EXPECT_EQ(parse_memory_size("512M"), 512 * kMiB);
  EXPECT_EQ(parse_memory_size("512mb"), 512 * kMiB);
  EXPECT_EQ(parse_memory_size("8G"), 8 * kGiB);
  EXPECT_EQ(parse_memory_size("1.5GiB"), 3 * kGiB / 2);
  EXPECT_EQ(parse_memory_size("2T"), 2 * 1024 * kGiB);
}

TEST(MemorySize, APercentageIsAShareOfTheMachinesMemory) {
  const std::uint64_t ram = physical_memory();
  ASSERT_GT(ram, 0u);
  EXPECT_EQ(parse_memory_size("100%"), ram);
  const double share = static_cast<double>(parse_memory_size("40%")) / static_cast<double>(ram);
  EXPECT_NEAR(share, 0.4, 1e-9);
}

TEST(MemorySize, AHugeSizeIsCappedNotWrapped) {
  EXPECT_EQ(parse_memory_size("1e30T"), static_cast<std::uint64_t>(1.8e19));
}

TEST(MemorySize, AnythingElseIsAnErrorQuotingTheText) {
  for (const std::string bad : {"", "abc", "0", "-1G", "12X", "8 G", "101%", "nan", "inf", "G"}) {
    try {
      (void)parse_memory_size(bad);
      ADD_FAILURE() << "'" << bad << "' was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "' is not a memory size"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace allanlot::workflow
