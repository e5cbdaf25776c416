// The watch workflow (docs/cli.md "Command: watch", docs/production.md): follows a recording
// that is still being written, judges it against a spec at looks every --interval seconds of data
// with the sequential rule of kernels/plan/sequential.hpp, and ends as soon as every limit is
// decided, reporting each look as it is made. The command line adds its
// options; the Python module's watch() runs it too.
#pragma once

#include "src/workflow/input_args.hpp"
#include "src/workflow/status.hpp"

#include "kernels/model/fit.hpp"

#include <array>
#include <iosfwd>
#include <span>
#include <string>

namespace allanlot::workflow {

/// Exit status of a recording still undecided when watching ends (--max-duration reached,
/// the recording stopped growing for --idle-timeout, or a --replay recording ended).
inline constexpr int kExitUndecided = 3;

struct WatchOptions {
  std::string recording;
  std::string spec_path;
  double interval_s = 600.0;       // seconds of recording between looks
  double max_duration_s = 0.0;     // the longest the recording is watched (the last look)
  double poll_s = 5.0;             // wall seconds between checks for new data
  double idle_timeout_s = 3600.0;  // wall seconds without new data before giving up
  bool replay = false;             // the recording is complete: look at it as it grew
  double confidence = 0.0;         // 0: the spec's
  int threads = 0;
  bool quiet = false;
  InputArgs input;
};

/// What a look judges: the fit of a channel's record so far, made as `analyze` makes it (the
/// overlapping Allan curve on 16 taus per decade with its edf, the eq. (3) fit from the first tau
/// the sensor's filter leaves unbiased, src/pipeline/channel_fit.hpp), so that a real sensor's
/// filter does not leave every look a poor fit.
struct LookFit {
  kernels::FitStatus status = kernels::FitStatus::NoData;
  std::array<kernels::TermFit, kernels::kNumTerms> terms{};
};
LookFit look_fit(std::span<const double> rate, double rate_hz, const std::string& units,
                 int threads);

/// Returns 0 when every limit is decided pass, 1 when one is decided fail, kExitUndecided
/// when watching ended with limits undecided (named on out), 2 on a usage error or a
/// recording that cannot be read.
int run_watch(const WatchOptions& opt, std::ostream& out, std::ostream& err);

}  // namespace allanlot::workflow
