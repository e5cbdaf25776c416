// Memory of an analyze run: the limit's text (--memory-limit, a share of the machine's memory of
// src/workflow/input_args.hpp), the process's peak, and the reuse of the channels' arrays from
// one channel to the next.
#pragma once

#include "kernels/common/large_vector.hpp"
#include "src/workflow/input_args.hpp"

#include <cstdint>
#include <string>

namespace allanlot::workflow {

/// Parses a memory size: "512M", "8G", "1.5GiB", "2000000000", or "40%" of the machine's RAM.
/// Throws std::invalid_argument naming the text.
std::uint64_t parse_memory_size(const std::string& text);

/// Peak resident memory of this process so far, in bytes.
std::uint64_t peak_rss_bytes();

/// For the lifetime of a batch run: channels' large arrays are reused from one channel to the
/// next (kernels/common/large_vector.hpp), holding at most a quarter of `memory_limit` (and
/// HugeBlockPool::kHeldBytes) between channels; and glibc keeps the medium arrays (a PSD's
/// 1 MiB bins, the sweeps' block sums: up to 32 MiB) in its heap rather than in fresh
/// mappings, which each channel would otherwise fault in and have zeroed again (15 000 of a
/// 90-minute unit's 27 000 page faults, docs/performance.md). The glibc setting is for the
/// process and stays.
class MemoryReuse {
public:
  explicit MemoryReuse(std::uint64_t memory_limit);

private:
  kernels::HugeBlockPool::Scope blocks_;
};

}  // namespace allanlot::workflow
