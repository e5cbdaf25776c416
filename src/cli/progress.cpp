#include "src/cli/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <unistd.h>

namespace allanlot::cli {
namespace {

std::string hms(double s) {
  const auto t = static_cast<long long>(std::max(0.0, s) + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", t / 3600, t / 60 % 60, t % 60);
  return buf;
}

}  // namespace

Progress::Progress(bool enabled, std::size_t total, std::ostream& err)
    : enabled_(enabled && total > 1 && isatty(2) == 1), total_(total), err_(err),
      start_(Clock::now()) {}

void Progress::clear() {
  if (!showing_) return;
  err_ << "\r\x1b[K" << std::flush;
  showing_ = false;
}

void Progress::update(std::size_t done, std::uint64_t samples) {
  samples_ += samples;
  if (!enabled_) return;
  const double el = std::chrono::duration<double>(Clock::now() - start_).count();
  const double left =
      done > 0 ? el / static_cast<double>(done) * static_cast<double>(total_ - done) : 0;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "allanlot: %zu/%zu recordings, %.1f M samples/s, elapsed %s, left ~%s", done,
                total_, el > 0 ? static_cast<double>(samples_) / el / 1e6 : 0.0, hms(el).c_str(),
                hms(left).c_str());
  clear();
  err_ << buf << (done < total_ ? "" : "\n") << std::flush;
  showing_ = done < total_;
}

}  // namespace allanlot::cli
