// The one cap on thread counts, for the command line and the Python module alike.
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <thread>

namespace allanlot::kernels {

/// The most threads a caller may ask for (--threads, the Python module's `threads`).
inline constexpr int kMaxThreads = 4096;

/// The most threads a region is given: four per hardware thread, far beyond any speed-up, and
/// at most kMaxThreads. Why a cap: libgomp itself crashes creating a team of 100 000 threads
/// and stalls at 20 000, whether they are asked by an argument or by OMP_NUM_THREADS.
inline int thread_cap() {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return static_cast<int>(std::min<unsigned>(4u * hw, static_cast<unsigned>(kMaxThreads)));
}

/// The thread count to hand to the kernels for `requested` (0: OpenMP's current maximum, i.e.
/// OMP_NUM_THREADS or all cores), at most thread_cap(); 1 in a build without OpenMP.
inline int capped_threads(int requested) {
#ifdef _OPENMP
  return std::clamp(requested > 0 ? requested : omp_get_max_threads(), 1, thread_cap());
#else
  (void)requested;
  return 1;
#endif
}

}  // namespace allanlot::kernels
