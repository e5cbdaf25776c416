// The one FFTW wrapper of the kernels: the planner lock, SIMD-aligned buffers and plans that are
// made and destroyed under that lock.
//
// Determinism: every plan is made with FFTW_ESTIMATE, so the algorithm is chosen by heuristics,
// not by timing, and every plan of a given size and layout rounds the same way in every run
// (FFTW_MEASURE could differ between runs and break byte reproducibility). The buffers come
// from fftw_malloc, which always aligns for SIMD, so the alignment a plan assumes holds for
// every buffer of this wrapper, including those a plan is later executed on (Plan::execute_r2c).
#pragma once

#include <fftw3.h>

#include <cstddef>
#include <memory>
#include <mutex>

namespace allanlot::kernels {

namespace detail {
/// The one mutex that serializes FFTW planning and plan destruction (FFTW's planner is not
/// thread-safe); every kernel that plans FFTW transforms must take it (fft::Plan does).
std::mutex& fftw_planner_mutex();
}  // namespace detail

namespace fft {

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};

/// `count` elements from fftw_malloc (SIMD-aligned, uninitialized).
template <class T>
using Buffer = std::unique_ptr<T[], FftwFree>;

/// Allocates a Buffer of `count` elements; throws std::bad_alloc when fftw_malloc fails.
template <class T>
Buffer<T> alloc(std::size_t count) {
  auto* p = static_cast<T*>(fftw_malloc(sizeof(T) * count));
  if (!p) throw std::bad_alloc();
  return Buffer<T>(p);
}

/// An FFTW_ESTIMATE plan, made and destroyed under detail::fftw_planner_mutex(). The factories
/// throw std::runtime_error("<who>: FFTW planning failed") when FFTW returns no plan. Movable,
/// not copyable; executing is thread-safe on distinct buffers (execute_r2c).
class Plan {
public:
  /// Real-to-complex transform of length n: in (n doubles) to out (n/2 + 1 bins); in == out
  /// reinterpreted is the in-place form (in then holds 2 (n/2 + 1) doubles).
  static Plan r2c(int n, double* in, fftw_complex* out, const char* who);
  /// The inverse, unnormalized (FFTW's convention: the round trip multiplies by n).
  static Plan c2r(int n, fftw_complex* in, double* out, const char* who);
  /// `howmany` real-to-complex transforms of length n, contiguous: transform b reads
  /// in[b n .. b n + n) and writes out[b (n/2 + 1) .. (b + 1)(n/2 + 1)).
  static Plan r2c_batch(int n, int howmany, double* in, fftw_complex* out, const char* who);

  Plan(Plan&& other) noexcept;
  Plan& operator=(Plan&& other) noexcept;
  Plan(const Plan&) = delete;
  Plan& operator=(const Plan&) = delete;
  ~Plan();

  /// Runs the transform on the buffers it was planned with.
  void execute() const;
  /// Runs a real-to-complex plan on other buffers of the same layout, allocated by fft::alloc
  /// (FFTW's new-array execute).
  void execute_r2c(double* in, fftw_complex* out) const;

private:
  explicit Plan(fftw_plan p) : plan_(p) {}
  fftw_plan plan_ = nullptr;
};

}  // namespace fft
}  // namespace allanlot::kernels
