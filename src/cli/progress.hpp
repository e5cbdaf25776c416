// The progress line of `analyze` (docs/lots-and-slurm.md "Progress").
#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace allanlot::cli {

/// On a terminal only (stderr a terminal): one line rewritten in place after every recording,
/// erased before anything else is printed, so that it never runs into a coefficient table or a
/// message. Logs (batch jobs, Slurm) get the closing lines alone.
class Progress {
public:
  Progress(bool enabled, std::size_t total, std::ostream& err);
  /// Erases the line (carriage return, erase to the end of the line: ECMA-48 EL).
  void clear();
  /// After `done` of the recordings, `samples` more samples read.
  void update(std::size_t done, std::uint64_t samples);

private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  std::size_t total_;
  std::ostream& err_;
  Clock::time_point start_;
  std::uint64_t samples_ = 0;
  bool showing_ = false;
};

}  // namespace allanlot::cli
