// Loops whose iterations an enclosing team may share: analyze models its poor fits as tasks of
// one team, one a channel, and the loops inside each model (its candidates, its grid searches,
// its replicas) as tasks too, so that a thread whose channels are done takes work from the
// longest one (docs/development.md "Threads and determinism").
#pragma once

#include "kernels/common/parallel.hpp"

#include <cstdint>

namespace allanlot::kernels {

/// Calls body(i) once for every i in [0, n), in any order and on any thread, and returns when
/// all are done. Inside an enclosing parallel region (analyze's poor fits, one task a channel)
/// the calls are tasks that any thread of that region may take when it has nothing else to do,
/// so that the longest channel's loops do not leave the other cores idle; outside, a team of
/// `threads` (1: a plain loop). `body` must write only what index i owns (and catch its
/// exceptions: ExceptionCollector), so that no result depends on the thread count or the order.
template <class F>
void for_each_index(std::int64_t n, int threads, F&& body) {
#ifdef _OPENMP
  auto* fn = &body;  // a pointer, so that each task copies the pointer and not the callable
  if (omp_in_parallel()) {
#pragma omp taskloop grainsize(1) firstprivate(fn)
    for (std::int64_t i = 0; i < n; ++i)
      (*fn)(i);
    return;
  }
  if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::int64_t i = 0; i < n; ++i)
      (*fn)(i);
    return;
  }
#else
  (void)threads;
#endif
  for (std::int64_t i = 0; i < n; ++i)
    body(i);
}

}  // namespace allanlot::kernels
