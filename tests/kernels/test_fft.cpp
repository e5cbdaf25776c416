// The one FFTW wrapper (kernels/spectral/fft.hpp): buffers aligned for every SIMD width FFTW
// uses, the real-to-complex transform and its unnormalized inverse on a signal whose
// transform is known, a plan run on other buffers giving the same bits, and plans that move.
// The stored wisdom of the Welch plans is checked by test_psd.cpp (PsdPlans).
#include "kernels/spectral/fft.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <utility>

namespace allanlot::kernels::fft {
namespace {

bool aligned(const void* p, std::uintptr_t to) {
  return reinterpret_cast<std::uintptr_t>(p) % to == 0;
}

TEST(Fft, BuffersAreAlignedForEverySimdWidth) {
  for (const std::size_t n : {1u, 3u, 1000u, 4097u})
    EXPECT_TRUE(aligned(alloc<double>(n).get(), 64)) << n;
  // 8 MiB and more: 2 MiB-aligned, as LargeVector's huge-page blocks.
  EXPECT_TRUE(aligned(alloc<double>(std::size_t{1} << 20).get(), std::uintptr_t{1} << 21));
}

TEST(Fft, ACosineIsTwoBinsAndTheRoundTripScalesByN) {
  // x_j = 3 + 2 cos(2 pi 5 j / n): X_0 = 3 n, X_5 = n (the cosine's half amplitude times n),
  // every other bin 0 (DFT, FFTW's sign convention e^{-2 pi i jk / n}).
  const int n = 96;
  const Buffer<double> x = alloc<double>(n);
  const Buffer<fftw_complex> spectrum = alloc<fftw_complex>(n / 2 + 1);
  const Buffer<double> back = alloc<double>(n);
  const Plan forward = Plan::r2c(n, x.get(), spectrum.get(), "test");
  const Plan inverse = Plan::c2r(n, spectrum.get(), back.get(), "test");
  for (int j = 0; j < n; ++j)
    x[j] = 3 + 2 * std::cos(2 * std::numbers::pi * 5 * j / n);
  forward.execute();
  for (int k = 0; k <= n / 2; ++k) {
    const double want = k == 0 ? 3.0 * n : k == 5 ? 1.0 * n : 0.0;
    EXPECT_NEAR(spectrum[k][0], want, 1e-12 * n) << k;
    EXPECT_NEAR(spectrum[k][1], 0.0, 1e-12 * n) << k;
  }

  inverse.execute();  // FFTW's c2r overwrites its input, checked above
  for (int j = 0; j < n; ++j)
    EXPECT_NEAR(back[j] / n, 3 + 2 * std::cos(2 * std::numbers::pi * 5 * j / n), 1e-13) << j;
}

TEST(Fft, APlanOnOtherBuffersGivesTheSameBits) {
  const int n = 1000;  // not a power of two
  const Buffer<double> a = alloc<double>(n), b = alloc<double>(n);
  const Buffer<fftw_complex> fa = alloc<fftw_complex>(n / 2 + 1),
                             fb = alloc<fftw_complex>(n / 2 + 1);
  const Plan plan = Plan::r2c(n, a.get(), fa.get(), "test");
  for (int j = 0; j < n; ++j)
    a[j] = b[j] = std::sin(0.37 * j) + 1e-3 * j;
  plan.execute();
  plan.execute_r2c(b.get(), fb.get());
  EXPECT_EQ(std::memcmp(fa.get(), fb.get(), sizeof(fftw_complex) * (n / 2 + 1)), 0);
}

TEST(Fft, APlanMovesAndIsDestroyedOnce) {
  const int n = 64;
  const Buffer<double> x = alloc<double>(n);
  const Buffer<fftw_complex> spectrum = alloc<fftw_complex>(n / 2 + 1);
  Plan a = Plan::r2c(n, x.get(), spectrum.get(), "test");
  Plan b = std::move(a);  // a holds no plan now; its destructor destroys nothing
  Plan c = Plan::r2c(n, x.get(), spectrum.get(), "test");
  c = std::move(b);  // c's first plan destroyed here, b's taken over
  for (int j = 0; j < n; ++j)
    x[j] = 1.0;
  c.execute();
  EXPECT_DOUBLE_EQ(spectrum[0][0], n);
}

}  // namespace
}  // namespace allanlot::kernels::fft
