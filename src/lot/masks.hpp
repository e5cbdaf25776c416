// ITU-T wander-generation masks: the MTIE and TDEV limits that telecom clocks are specified
// against, as spec limits (`"mtie": {"mask": "G.811"}` in a spec file's channel rule,
// docs/formats.md "Spec file") and as curves on the report's time-error plots
// (docs/hat-and-masks.md). One table (masks.cpp) holds every mask, each segment with the
// recommendation and table it comes from.
#pragma once

#include "kernels/allan/stat_result.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::masks {

/// One piece of a mask: on lo_s < tau <= hi_s (the first piece includes lo_s), the limit is
/// (a + b tau^p) ns.
struct Segment {
  double lo_s, hi_s;
  double a_ns, b_ns, p;
};

struct Mask {
  std::string_view name;    // as a spec names it: "G.811", "G.813", "G.8262", "G.8262-option2"
  std::string_view stat;    // "mtie" or "tdev"
  std::string_view clock;   // what the mask is for, in words
  std::string_view source;  // the recommendation and table
  std::span<const Segment> segments;
};

/// Every mask, in a fixed order (by recommendation, MTIE before TDEV).
std::span<const Mask> all_masks();

/// The mask `name` of statistic `stat` ("mtie" or "tdev"), nullptr when there is none.
const Mask* find_mask(std::string_view name, std::string_view stat);

/// The names that have a mask of `stat`, joined by ", " (for messages).
std::string mask_names(std::string_view stat);

/// The limit in seconds at tau_s; NaN outside the mask's taus.
double limit_s(const Mask& m, double tau_s);

/// The mask's first and last tau (s).
double first_tau_s(const Mask& m);
double last_tau_s(const Mask& m);

/// A curve against a mask, per tau, on the taus inside the mask: fail when a tau's lower
/// bound (dev_lo where the statistic has an interval, as TDEV does; else dev, as for MTIE,
/// which has none) exceeds the limit; else undecided when a tau's upper bound (dev_hi, else dev)
/// does; else pass. No tau inside the mask: undecided. `worst` is the tau whose dev / limit is
/// largest, `detail` the decision in words, e.g. "mtie 3.1e-07 s > G.811 3e-07 s at tau 1000 s".
struct CurveVerdict {
  enum class Outcome { Pass, Fail, Undecided } outcome = Outcome::Undecided;
  double worst_tau_s = 0;
  std::string detail;
};
CurveVerdict judge_curve(const Mask& m, const kernels::StatResult& curve);

}  // namespace allanlot::masks
