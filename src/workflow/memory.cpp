#include "src/workflow/memory.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

namespace allanlot::workflow {

std::uint64_t parse_memory_size(const std::string& text) {
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(text, &pos);
  } catch (const std::exception&) {
    throw std::invalid_argument("'" + text + "' is not a memory size (e.g. 8G, 512M, 40%)");
  }
  std::string unit = text.substr(pos);
  for (auto& c : unit)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  double scale = 0;
  if (unit.empty() || unit == "B")
    scale = 1;
  else if (unit == "K" || unit == "KB" || unit == "KIB")
    scale = 1024.0;
  else if (unit == "M" || unit == "MB" || unit == "MIB")
    scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "GB" || unit == "GIB")
    scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "TB" || unit == "TIB")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else if (unit == "%")
    scale = static_cast<double>(physical_memory()) / 100.0;
  if (!(scale > 0) || !(v > 0) || !std::isfinite(v) || (unit == "%" && v > 100))
    throw std::invalid_argument("'" + text + "' is not a memory size (e.g. 8G, 512M, 40%)");
  return static_cast<std::uint64_t>(std::min(v * scale, 1.8e19));
}

// getrusage gives kilobytes on Linux.
std::uint64_t peak_rss_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<std::uint64_t>(ru.ru_maxrss) * 1024;
}

MemoryReuse::MemoryReuse(std::uint64_t memory_limit)
    : blocks_(static_cast<std::size_t>(
          std::min<std::uint64_t>(kernels::HugeBlockPool::kHeldBytes, memory_limit / 4))) {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace allanlot::workflow
