// The one FFTW wrapper of the kernels: the planner lock, SIMD-aligned buffers and plans that are
// made and destroyed under that lock.
//
// Determinism: no plan is chosen by timing in a run (FFTW_MEASURE at run time could choose
// differently from run to run and break byte reproducibility). Plans are made with
// FFTW_ESTIMATE (heuristics), or, for the Welch PSD's transforms, from the wisdom stored with
// allanlot (fft_wisdom.txt, measured once; Plan::r2c_stored): either way a plan is a function
// of the transform and the CPU's SIMD level, so every run rounds the same way. The buffers
// come from fft::alloc, aligned to 64 bytes (every SIMD width FFTW uses), so the alignment a
// plan assumes holds for every buffer of this wrapper, including those a plan is later
// executed on (Plan::execute_r2c).
#pragma once

#include <fftw3.h>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace allanlot::kernels {

namespace detail {
/// The one mutex that serializes FFTW planning and plan destruction (FFTW's planner is not
/// thread-safe); every kernel that plans FFTW transforms must take it (fft::Plan does).
std::mutex& fftw_planner_mutex();
}  // namespace detail

namespace fft {

/// The storage behind alloc (free it with std::free).
void* allocate_aligned(std::size_t bytes);

struct AlignedFree {
  void operator()(void* p) const { std::free(p); }
};

/// `count` elements, 64-byte aligned, uninitialized (alloc).
template <class T>
using Buffer = std::unique_ptr<T[], AlignedFree>;

/// Allocates a Buffer of `count` elements, 64-byte aligned; blocks of 8 MiB and more are 2
/// MiB-aligned and advised for transparent huge pages, as LargeVector's
/// (kernels/common/large_vector.hpp: a fresh Welch buffer of 4 KiB pages costs more in page
/// faults than its FFTs). Throws std::bad_alloc when the allocation fails.
template <class T>
Buffer<T> alloc(std::size_t count) {
  return Buffer<T>(static_cast<T*>(allocate_aligned(sizeof(T) * count)));
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
  /// Real-to-complex transform of length n planned from the wisdom stored with allanlot
  /// (kernels/spectral/fft_wisdom.txt: FFTW_MEASURE plans of the powers of two the Welch PSD
  /// uses, measured once by bench/make_fft_wisdom on this project's machine kind), or with
  /// FFTW_ESTIMATE where that wisdom has no plan for n or this CPU lacks its SIMD level;
  /// `*from_wisdom` says which. The wisdom is imported and forgotten under the planner lock, so
  /// no other plan (the simulator's, the PSD fit's) ever sees it and theirs keep their bits.
  static Plan r2c_stored(int n, double* in, fftw_complex* out, const char* who,
                         bool* from_wisdom = nullptr);

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

/// FFTW wisdom (FFTW's text format) for the real-to-complex transforms of the given lengths,
/// measured now with FFTW_MEASURE on scratch buffers: what bench/make_fft_wisdom writes into
/// kernels/spectral/fft_wisdom.txt. Takes the planner lock; the wisdom is forgotten afterwards.
std::string measure_r2c_wisdom(const std::vector<int>& lengths);

}  // namespace fft
}  // namespace allanlot::kernels
