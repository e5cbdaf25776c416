// The dynamic Allan deviation (Stable32's DAVAR; Galleani & Tavella, "The dynamic Allan
// variance", IEEE Trans. UFFC 56(3), 2009): the overlapping Allan deviation of a window sliding
// along the record, which shows how the noise changes with time (a clock's warm-up or a jump in
// its noise, an IMU's warm-up). No numerics of its own: each window is an ordinary record,
// built into phase and passed to oadev (allan.hpp) as the slice alone would be.
#pragma once

#include "kernels/allan/phase.hpp"

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Window and step of the dynamic deviation (docs/cli.md `--dynamic WINDOW[:STEP]`).
struct DynamicSpec {
  double window = 0;  // the window's length: samples, or seconds when in_seconds; 0 = off
  double step = 0;    // the step between windows, same unit; 0 = a quarter of the window
  bool in_seconds = false;
  bool enabled() const { return window > 0; }
};

/// Parses "WINDOW[:STEP]", each a positive number of samples or, with the suffix s, seconds
/// ("4096", "3600s:600s"). Throws std::invalid_argument naming the text.
DynamicSpec parse_dynamic_spec(std::string_view text);

/// Most windows a dynamic deviation has (a larger step is asked for beyond it): the heat map
/// is one column per window, and each costs an OADEV of its own.
inline constexpr std::int64_t kMaxDynamicWindows = 4096;

struct DynamicAdev {
  std::int64_t window = 0, step = 0;  // samples
  std::vector<std::int64_t> m;        // the averaging factors, the same for every window
  std::vector<double> tau_s;          // m * tau0
  std::vector<double> t_center_s;     // each window's centre, seconds from the first sample
  // oadev[w * m.size() + j]: window w at m[j]; NaN where the window has no value there (a
  // window whose samples are all missing, or a gap that leaves no term).
  std::vector<double> oadev;
};

/// The overlapping Allan deviation at the octave m (1, 2, 4, ... up to Stable32's largest for the
/// window) of every window of `window` samples starting at 0, step, 2 step, ... (the last one
/// ending at or before the record's end). Window w is oadev(make_phase(samples[w step ..
/// w step + window), type, rate_hz), m, 1): bit for bit what the slice alone gives. Windows run
/// in parallel, one thread each, so the result does not depend on `nthreads`. Preconditions
/// (std::invalid_argument naming them): rate_hz > 0, 3 <= window <= samples.size(), step >= 1,
/// at most kMaxDynamicWindows windows.
DynamicAdev dynamic_oadev(std::span<const double> samples, DataType type, double rate_hz,
                          std::int64_t window, std::int64_t step, int nthreads = 0);

}  // namespace allanlot::kernels
