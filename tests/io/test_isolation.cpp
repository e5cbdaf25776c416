// io/isolation: a reading that crashes, throws, loops or allocates without bound in the child
// ends as an io::Error naming the file in the parent, which goes on.
#include "io/error.hpp"
#include "io/isolation.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <new>
#include <string>
#include <vector>

namespace allanlot {
namespace {

std::string reason_of(const std::function<void()>& work, const io::IsolationLimits& limits = {}) {
  try {
    io::run_isolated("/data/unit7.h5", work, limits);
  } catch (const io::Error& e) {
    EXPECT_EQ(e.file(), "/data/unit7.h5");
    return e.reason();
  }
  return "";
}

TEST(Isolation, AWorkThatReturnsReturns) {
  EXPECT_EQ(reason_of([] {}), "");
}

TEST(Isolation, TheChildsErrorIsThrownInTheParentAsThrown) {
  try {
    io::run_isolated("/data/unit7.h5",
                     [] { throw io::Error("/data/unit7.h5", "/imu/gyro_x", "H5Aread failed"); });
    FAIL() << "no error";
  } catch (const io::Error& e) {
    EXPECT_EQ(e.dataset(), "/imu/gyro_x");
    EXPECT_EQ(e.reason(), "H5Aread failed");
  }
}

TEST(Isolation, ACrashOfTheChildIsAnErrorOfTheFile) {
  // Killed by the signal (under a sanitizer that keeps its own handler, by its report's abort
  // or exit status): the file's error either way.
  const std::string why = reason_of([] { std::raise(SIGSEGV); });
  EXPECT_NE(why.find("the HDF5 library"), std::string::npos) << why;
  EXPECT_NE(why.find("damaged or not a valid HDF5 file"), std::string::npos) << why;
  // The parent goes on: a second child runs as the first did.
  EXPECT_EQ(reason_of([] {}), "");
}

TEST(Isolation, AChildThatNeverEndsIsKilledAtTheWallBound) {
  io::IsolationLimits limits;
  limits.wall = std::chrono::seconds(1);
  const std::string why = reason_of(
      [] {
        for (;;)
          ::pause();
      },
      limits);
  EXPECT_NE(why.find("took more than 1 s"), std::string::npos) << why;
}

TEST(Isolation, AnAllocationBeyondTheBoundIsAnError) {
  // bad_alloc as RLIMIT_AS makes it (the sanitizers' runtimes cannot run under that limit, so
  // the allocation fails by being thrown directly there: the message is the same).
  const std::string why = reason_of([] { throw std::bad_alloc(); });
  EXPECT_NE(why.find("MiB of memory"), std::string::npos) << why;
}

TEST(Isolation, InsideTheChildNothingIsIsolatedTwice) {
  EXPECT_FALSE(io::in_isolated_child());
  const std::string why = reason_of([] {
    if (!io::in_isolated_child()) throw io::Error("f", "", "not in the child");
    io::run_isolated("f", [] { throw io::Error("f", "", "ran in the same child"); });
  });
  EXPECT_EQ(why, "ran in the same child");
}

}  // namespace
}  // namespace allanlot
