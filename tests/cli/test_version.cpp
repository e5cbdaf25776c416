#include <gtest/gtest.h>

#include <cstdio>
#include <string>

TEST(Cli, BinaryRuns) {
  FILE* f = popen((std::string(ALLANLOT_BINARY) + " --version").c_str(), "r");
  ASSERT_NE(f, nullptr);
  char buf[256] = {};
  ASSERT_NE(fgets(buf, sizeof buf, f), nullptr);
  EXPECT_EQ(pclose(f), 0);
  EXPECT_EQ(std::string(buf).rfind("allanlot ", 0), 0u);
}
