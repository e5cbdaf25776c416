// The large-array storage (kernels/common/large_vector.hpp): blocks freed inside a
// HugeBlockPool::Scope are handed to the next array of their size, never to a much smaller
// one, never beyond the scope's limit, and all go back to the system when the scope ends.
#include "kernels/common/large_vector.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace allanlot::kernels {
namespace {

constexpr std::size_t kChannel = 5'400'000;  // a 90-minute 1 kHz channel: 43.2 MB of doubles

TEST(HugeBlockPool, AChannelsBlockIsReusedInsideAScopeOnly) {
  const double* first = nullptr;
  {
    const HugeBlockPool::Scope scope;
    {
      LargeVector<double> a(kChannel);
      a[0] = 1.0;
      first = a.data();
    }
    // One sample more (the phase of the same channel) rounds to the same 2 MiB pages.
    LargeVector<double> b(kChannel + 1);
    EXPECT_EQ(b.data(), first);
  }
  // Outside any scope nothing is held: the pool gives nothing back.
  EXPECT_EQ(HugeBlockPool::pool().take(rounded_to_huge_pages(kChannel * sizeof(double))), nullptr);
}

TEST(HugeBlockPool, NoBigBlockForASmallArrayAndNothingBeyondTheLimit) {
  const HugeBlockPool::Scope scope(rounded_to_huge_pages(kChannel * sizeof(double)));
  const double* big = nullptr;
  {
    LargeVector<double> a(kChannel);
    big = a.data();
  }
  {
    // Half the size: the held block is more than an eighth too big for it.
    LargeVector<double> half(kChannel / 2);
    EXPECT_NE(half.data(), big);
    LargeVector<double> again(kChannel);
    EXPECT_EQ(again.data(), big);
    LargeVector<double> second(kChannel);
  }  // three blocks freed: the limit holds one, the others go back to the system
  const std::size_t rounded = rounded_to_huge_pages(kChannel * sizeof(double));
  void* held = HugeBlockPool::pool().take(rounded);
  EXPECT_NE(held, nullptr);
  EXPECT_EQ(HugeBlockPool::pool().take(rounded), nullptr);
  HugeBlockPool::pool().give(held, rounded);
}

}  // namespace
}  // namespace allanlot::kernels
