// Storage for the large per-channel arrays (a channel's phase points: 43 MB for a 90-minute
// 1 kHz channel), where the cost is not the arithmetic but the memory's first touch: on a
// fresh allocation every 4 KiB page faults once (about 10 000 faults for one channel, a large
// share of building the phase on a virtual machine). Blocks of at least kHugeBytes are
// allocated 2 MiB-aligned and advised for transparent huge pages (madvise(2) MADV_HUGEPAGE;
// mere advice, ignored where THP is off), which makes it 512 times fewer faults; and elements
// are default-initialized, so that resize() does not write zeros the producer overwrites.
//
// Within a HugeBlockPool::Scope (a batch run), freed blocks are kept for reuse instead of
// returned to the system: a unit's channels all need blocks of the same few sizes, and a block
// taken back from the pool is already mapped, so the next channel neither faults its pages in
// again nor has the kernel zero them (0.45 s of system time for a six-channel 90-minute unit
// before, docs/performance.md).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include <sys/mman.h>

namespace allanlot::kernels {

inline constexpr std::size_t kHugePage = std::size_t{2} << 20;
inline constexpr std::size_t kHugeBytes = std::size_t{8} << 20;

inline std::size_t rounded_to_huge_pages(std::size_t bytes) {
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}

/// `bytes` (at least kHugeBytes) 2 MiB-aligned and advised for transparent huge pages (mere
/// advice, ignored where THP is off); free it with std::free. Throws std::bad_alloc.
inline void* allocate_huge(std::size_t bytes) {
  const std::size_t rounded = rounded_to_huge_pages(bytes);
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (!p) throw std::bad_alloc();
  madvise(p, rounded, MADV_HUGEPAGE);
  return p;
}

/// Freed blocks of allocate_huge kept for reuse while a Scope is alive (see the file comment).
/// A block is reused for a request of its own size or up to an eighth less (the arrays of one
/// channel differ by a sample or two, and the pool must not hand a big block to a small
/// array; a block keeps the size it was asked for); at most the smallest live Scope's
/// `max_held` bytes are held, beyond that a freed block goes back to the system, and the last
/// Scope to end frees them all, so that outside a batch run nothing stays mapped.
class HugeBlockPool {
public:
  static constexpr std::size_t kHeldBytes = std::size_t{384} << 20;

  /// Enables the pool from construction to destruction (nestable; any thread).
  class Scope {
  public:
    explicit Scope(std::size_t max_held = kHeldBytes) { pool().enter(max_held); }
    ~Scope() { pool().leave(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
  };

  /// A held block of `rounded` bytes (a multiple of kHugePage) or a little more, else nullptr.
  void* take(std::size_t rounded) {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::size_t best = blocks_.size();
    for (std::size_t i = 0; i < blocks_.size(); ++i)
      if (blocks_[i].bytes >= rounded && blocks_[i].bytes - rounded <= rounded / 8 &&
          (best == blocks_.size() || blocks_[i].bytes < blocks_[best].bytes))
        best = i;
    if (best == blocks_.size()) return nullptr;
    void* p = blocks_[best].p;
    held_ -= blocks_[best].bytes;
    blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(best));
    return p;
  }
  /// Keeps the block of `rounded` bytes for reuse, or frees it (no Scope, or the pool full).
  void give(void* p, std::size_t rounded) noexcept {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (scopes_ > 0 && held_ + rounded <= max_held_) {
        try {
          blocks_.push_back({p, rounded});
          held_ += rounded;
          return;
        } catch (...) {  // no room to note it: the block is simply freed
        }
      }
    }
    std::free(p);
  }
  static HugeBlockPool& pool() {
    static HugeBlockPool instance;
    return instance;
  }

private:
  struct Block {
    void* p;
    std::size_t bytes;
  };
  void enter(std::size_t max_held) {
    const std::lock_guard<std::mutex> lock(mutex_);
    max_held_ = scopes_++ == 0 ? max_held : std::min(max_held_, max_held);
  }
  void leave() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (--scopes_ > 0) return;
    for (const Block& b : blocks_)
      std::free(b.p);
    blocks_.clear();
    held_ = 0;
  }
  std::mutex mutex_;
  std::vector<Block> blocks_;
  std::size_t held_ = 0;
  std::size_t max_held_ = 0;
  int scopes_ = 0;
};

template <class T>
struct LargeAllocator {
  using value_type = T;

  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugeBytes) return std::allocator<T>{}.allocate(n);
    if (void* p = HugeBlockPool::pool().take(rounded_to_huge_pages(bytes)))
      return static_cast<T*>(p);
    return static_cast<T*>(allocate_huge(bytes));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugeBytes)
      std::allocator<T>{}.deallocate(p, n);
    else
      HugeBlockPool::pool().give(p, rounded_to_huge_pages(n * sizeof(T)));
  }
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  friend bool operator==(const LargeAllocator&, const LargeAllocator&) { return true; }
};

/// A std::vector for large arrays of trivially constructible T (see above).
template <class T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace allanlot::kernels
