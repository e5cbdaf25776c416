// How a round chooses between look-alikes (docs/diagnose.md, "Ramp, random walk and hump told
// apart"): a Gauss-Markov hump against the simpler process it becomes in a limit of tau_c.
#include "kernels/diagnose/internal.hpp"

#include <string>

namespace allanlot::kernels::diagnose_detail {

// A Gauss-Markov process is a random walk at taus well below its tau_c (K^2 = 2 sigma^2 /
// tau_c, diagnose.hpp) and white noise well above it (N^2 = 2 sigma^2 tau_c): each is the
// Gauss-Markov candidate in a limit of tau_c, so the hump is told apart from them by its
// turnover. When the markov candidate wins a round and the random walk or
// white candidate is significant too, the hump is named only when its turnover is measured:
// its peak, near 1.9 tau_c, has at least an octave of taus beyond it on the side of the
// simpler process's limit (above it for a random walk, below it for white noise). Else the
// simpler process is named. Without this rule a random walk whose longest taus fall low by
// chance is named markov with its peak near the last tau in 1 of 10 records at every level of
// the study, while real gyroscopes' humps (tau_c 85-520 s in 10^4 s records) turn over well inside.
// A significance test of the turnover on top (the nested chi-square difference above its 95 %
// quantile) was tried and dropped: it named a random walk on imu5 gyro_y, whose hump fits
// within noise and the random walk does not (gap 1.13 against 1.29, replicas' p95 1.15-1.22).
std::size_t prefer_nested(const std::vector<CandidateFit>& cands, std::size_t best, const Curve& cv,
                          std::string& note) {
  if (best == cands.size() || cands[best].info.effect != Effect::Markov) return best;
  const std::size_t simpler =
      strongest(cands, [](Effect e) { return e == Effect::RandomWalk || e == Effect::White; });
  if (simpler == cands.size()) return best;
  const double peak = 1.9 * cands[best].fit.comps[cands[best].added].nl;
  const bool walk = cands[simpler].info.effect == Effect::RandomWalk;
  if (walk ? 2.0 * peak <= cv.tau.back() : peak >= 2.0 * cv.tau.front()) return best;
  note = "markov's turnover (peak near " + std::to_string(peak) + " s) is not within the taus " +
         "measured, so it is not told from " +
         std::string(effect_name(cands[simpler].info.effect)) + ", which is named";
  return simpler;
}

}  // namespace allanlot::kernels::diagnose_detail
