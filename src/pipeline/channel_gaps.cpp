#include "src/pipeline/channel_gaps.hpp"

#include <span>
#include <string>

namespace allanlot::pipeline {

kernels::PhaseData channel_phase(io::ChannelResult& r, const io::ChannelInfo& channel,
                                 kernels::LargeVector<double>& samples,
                                 const kernels::GapPolicy& policy, int nthreads) {
  kernels::GapFill fill;
  kernels::PhaseData phase =
      kernels::make_phase(std::span<double>(samples.data(), samples.size()), channel.data_type,
                          channel.sample_rate_hz, policy, &fill, nthreads);
  r.n_gaps = fill.missing;
  if (fill.missing == 0) return phase;
  r.gap_policy = kernels::to_string(policy);
  r.n_filled = fill.filled;
  r.filled_runs = fill.filled_runs;
  r.gap_runs_left = fill.runs_left;
  // The one place a reader of the terminal, the notes attribute and the report learns that
  // samples were estimated rather than measured.
  std::string note = "gaps (" + r.gap_policy + "): " + std::to_string(fill.missing) +
                     " missing samples in " + std::to_string(fill.runs) + " runs; " +
                     std::to_string(fill.filled) + " filled by interpolation in " +
                     std::to_string(fill.filled_runs) + " runs";
  if (fill.runs_left > 0)
    note += ", " + std::to_string(fill.missing_left) + " left as gaps in " +
            std::to_string(fill.runs_left) + " runs (terms touching them left out)";
  r.notes += (r.notes.empty() ? "" : "; ") + note;
  return phase;
}

}  // namespace allanlot::pipeline
