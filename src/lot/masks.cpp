// The masks' values, each from the recommendation and table named beside it. Every limit is in
// ns, over observation intervals tau in s; the segments join (to the tables' rounding) where
// they meet.
#include "src/lot/masks.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace allanlot::masks {
namespace {

// ITU-T G.811 (09/1997), primary reference clock (PRC), wander generation: Table 1 (MTIE,
// 0.275e-3 tau + 0.025 us up to 1000 s, then 1e-5 tau + 0.29 us) and Table 2 (TDEV: 3 ns up
// to 100 s, 0.03 tau ns up to 1000 s, 30 ns up to 10000 s). MTIE's second piece has no upper
// end in the table; 1e5 s bounds it here, beyond any record the report or spec sees judged.
constexpr Segment kG811Mtie[] = {{0.1, 1000.0, 25.0, 0.275, 1.0}, {1000.0, 1e5, 290.0, 0.01, 1.0}};
constexpr Segment kG811Tdev[] = {
    {0.1, 100.0, 3.0, 0.0, 0.0}, {100.0, 1000.0, 0.0, 0.03, 1.0}, {1000.0, 1e4, 30.0, 0.0, 0.0}};

// ITU-T G.813 (03/2003), synchronous equipment clock (SEC) option 1, wander generation at
// constant temperature: Table 1 (MTIE: 40 ns up to 1 s, 40 tau^0.1 ns up to 100 s,
// 25.25 tau^0.2 ns up to 1000 s) and Table 3 (TDEV: 3.2 ns up to 25 s, 0.64 tau^0.5 ns up to
// 100 s, 6.4 ns up to 1000 s). ITU-T G.8262/Y.1362 (07/2010), Ethernet equipment clock (EEC)
// option 1, repeats them as its Table 1 (MTIE) and Table 3 (TDEV).
constexpr Segment kSecMtie[] = {
    {0.1, 1.0, 40.0, 0.0, 0.0}, {1.0, 100.0, 0.0, 40.0, 0.1}, {100.0, 1000.0, 0.0, 25.25, 0.2}};
constexpr Segment kSecTdev[] = {
    {0.1, 25.0, 3.2, 0.0, 0.0}, {25.0, 100.0, 0.0, 0.64, 0.5}, {100.0, 1000.0, 6.4, 0.0, 0.0}};

// ITU-T G.8262/Y.1362 (07/2010), EEC option 2, wander generation at constant temperature:
// Table 4 (MTIE: 20 ns up to 1 s, 20 tau^0.48 ns up to 10 s, 60 ns up to 1000 s) and Table 5
// (TDEV: 3.2 tau^-0.5 ns up to 2.5 s, 2 ns up to 40 s, 0.32 tau^0.5 ns up to 1000 s, 10 ns up
// to 10000 s).
constexpr Segment kEec2Mtie[] = {
    {0.1, 1.0, 20.0, 0.0, 0.0}, {1.0, 10.0, 0.0, 20.0, 0.48}, {10.0, 1000.0, 60.0, 0.0, 0.0}};
constexpr Segment kEec2Tdev[] = {{0.1, 2.5, 0.0, 3.2, -0.5},
                                 {2.5, 40.0, 2.0, 0.0, 0.0},
                                 {40.0, 1000.0, 0.0, 0.32, 0.5},
                                 {1000.0, 1e4, 10.0, 0.0, 0.0}};

constexpr const char* kPrc = "primary reference clock (PRC)";
constexpr const char* kSec = "synchronous equipment clock (SEC), option 1";
constexpr const char* kEec1 = "Ethernet equipment clock (EEC), option 1";
constexpr const char* kEec2 = "Ethernet equipment clock (EEC), option 2";

constexpr Mask kMasks[] = {
    {"G.811", "mtie", kPrc, "ITU-T G.811 (09/1997) Table 1", kG811Mtie},
    {"G.811", "tdev", kPrc, "ITU-T G.811 (09/1997) Table 2", kG811Tdev},
    {"G.813", "mtie", kSec, "ITU-T G.813 (03/2003) Table 1", kSecMtie},
    {"G.813", "tdev", kSec, "ITU-T G.813 (03/2003) Table 3", kSecTdev},
    {"G.8262", "mtie", kEec1, "ITU-T G.8262/Y.1362 (07/2010) Table 1", kSecMtie},
    {"G.8262", "tdev", kEec1, "ITU-T G.8262/Y.1362 (07/2010) Table 3", kSecTdev},
    {"G.8262-option2", "mtie", kEec2, "ITU-T G.8262/Y.1362 (07/2010) Table 4", kEec2Mtie},
    {"G.8262-option2", "tdev", kEec2, "ITU-T G.8262/Y.1362 (07/2010) Table 5", kEec2Tdev},
};

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

std::span<const Mask> all_masks() {
  return kMasks;
}

const Mask* find_mask(std::string_view name, std::string_view stat) {
  for (const Mask& m : kMasks)
    if (m.name == name && m.stat == stat) return &m;
  return nullptr;
}

std::string mask_names(std::string_view stat) {
  std::string s;
  for (const Mask& m : kMasks)
    if (m.stat == stat) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

double first_tau_s(const Mask& m) {
  return m.segments.front().lo_s;
}

double last_tau_s(const Mask& m) {
  return m.segments.back().hi_s;
}

double limit_s(const Mask& m, double tau_s) {
  if (!(tau_s >= first_tau_s(m) && tau_s <= last_tau_s(m)))
    return std::numeric_limits<double>::quiet_NaN();
  for (const Segment& s : m.segments)
    if (tau_s <= s.hi_s) return 1e-9 * (s.a_ns + s.b_ns * std::pow(tau_s, s.p));
  return std::numeric_limits<double>::quiet_NaN();
}

CurveVerdict judge_curve(const Mask& m, const kernels::StatResult& c) {
  using O = CurveVerdict::Outcome;
  CurveVerdict v;
  bool any = false, fail = false, straddle = false;
  double worst = -1.0;
  std::size_t wi = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double lim = limit_s(m, c.tau_s[i]);
    if (!std::isfinite(lim) || !std::isfinite(c.dev[i])) continue;
    any = true;
    const double lo = i < c.dev_lo.size() && std::isfinite(c.dev_lo[i]) ? c.dev_lo[i] : c.dev[i];
    const double hi = i < c.dev_hi.size() && std::isfinite(c.dev_hi[i]) ? c.dev_hi[i] : c.dev[i];
    fail = fail || lo > lim;
    straddle = straddle || hi > lim;
    if (c.dev[i] / lim > worst) {
      worst = c.dev[i] / lim;
      wi = i;
    }
  }
  const std::string stat(m.stat), name(m.name);
  if (!any) {
    v.detail = stat + " has no tau in " + name + "'s " + num(first_tau_s(m)) + ".." +
               num(last_tau_s(m)) + " s";
    return v;
  }
  v.outcome = fail ? O::Fail : straddle ? O::Undecided : O::Pass;
  v.worst_tau_s = c.tau_s[wi];
  const char* rel = fail ? " > " : straddle ? " ~ " : " <= ";
  v.detail = stat + " " + num(c.dev[wi]) + " s" + rel + name + " " + num(limit_s(m, c.tau_s[wi])) +
             " s at tau " + num(c.tau_s[wi]) + " s";
  return v;
}

}  // namespace allanlot::masks
