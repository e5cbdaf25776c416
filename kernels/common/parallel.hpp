// OpenMP shims so that every kernel builds with ALLANLOT_USE_OPENMP=OFF, and one place that
// decides how many threads a region gets (docs/development.md "Threads and determinism":
// every region names its thread count).
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

#include <exception>
#include <mutex>

namespace allanlot::kernels {

/// Thread count for a parallel region: `requested` when > 0, otherwise OpenMP's current
/// maximum (OMP_NUM_THREADS or all cores); always 1 in a build without OpenMP.
inline int resolve_threads(int requested) {
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_max_threads();
#else
  (void)requested;
  return 1;
#endif
}

/// Captures the first exception thrown inside an OpenMP region so that it can be rethrown on
/// the calling thread after the region (exceptions must never leave an OpenMP region), as
/// pocketfft's thread_map does.
class ExceptionCollector {
public:
  template <class F>
  void run(F&& f) noexcept {
    try {
      f();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!first_) first_ = std::current_exception();
    }
  }
  void rethrow() const {
    if (first_) std::rethrow_exception(first_);
  }

private:
  std::mutex mutex_;
  std::exception_ptr first_;
};

}  // namespace allanlot::kernels
