// Private to the Allan-family kernels: a parallel driver for the statistics whose per-tau work
// is not one of the shared sweeps (kernels/allan/detail/sweep.hpp): MTIE, TIE rms, Theo1, the
// total family, PDEV. Each m's range of terms [0, count) is cut into chunks whose bounds
// depend only on m and count, never on the thread count; every (m, chunk) pair is one OpenMP
// work item that one thread computes in a fixed order, and the chunk values of an m are then
// combined in chunk order on the calling thread. So the result is bit-identical for any
// thread count (docs/development.md "Threads and determinism"), and a few large m still share
// the threads (the work of these statistics grows with m, so parallel over m alone would leave
// one thread with the largest m).
#pragma once

#ifndef ALLANLOT_KERNELS_FAMILY_HEADER
#error "kernels/allan/detail/chunked.hpp is private: include a family header first"
#endif

#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace allanlot::kernels::detail {

/// One work item: terms [begin, end) of m_list[j].
struct Chunk {
  std::size_t j = 0;
  std::int64_t begin = 0, end = 0;
};

/// The chunks of every m: `count(m)` terms in pieces of `size(m)` (>= 1) terms.
template <class Count, class Size>
std::vector<Chunk> make_chunks(std::span<const std::int64_t> m_list, Count count, Size size) {
  std::vector<Chunk> out;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    const std::int64_t n = count(m_list[j]);
    const std::int64_t s = std::max<std::int64_t>(1, size(m_list[j]));
    for (std::int64_t b = 0; b < n; b += s)
      out.push_back({j, b, std::min(n, b + s)});
  }
  return out;
}

/// Runs `work(m, begin, end) -> V` for every chunk in parallel and folds each m's values in
/// chunk order with `fold(V& acc, const V& v)`, starting from V{}. `work` must not throw.
template <class V, class Work, class Fold>
std::vector<V> run_chunks(std::span<const std::int64_t> m_list, const std::vector<Chunk>& chunks,
                          int nthreads, Work work, Fold fold) {
  std::vector<V> part(chunks.size());
  const auto count = static_cast<std::int64_t>(chunks.size());
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t c = 0; c < count; ++c) {
    const Chunk& k = chunks[static_cast<std::size_t>(c)];
    part[static_cast<std::size_t>(c)] = work(m_list[k.j], k.begin, k.end);
  }
  std::vector<V> out(m_list.size());
  for (std::size_t c = 0; c < chunks.size(); ++c)
    fold(out[chunks[c].j], part[c]);
  return out;
}

}  // namespace allanlot::kernels::detail
