// The unit curves of the humps and resonances a diagnosis fits (basis_of), kept per thread so
// that each is computed once.
#include "kernels/diagnose/internal.hpp"

#include <bit>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace allanlot::kernels::diagnose_detail {
namespace {

// The unit curves of the humps and resonances already computed on this thread, by their exact
// inputs: a round's ten candidates, each search's trials and the final refit fit the same
// components again and again beside the one that moves, and under a filter each curve is a
// quadrature per tau (lowpass_markov_avar, resonance_avar), which took a third of a modelled
// ADIS16405 accelerometer's time. A hit returns the very numbers a recomputation would, so no
// result depends on the cache or on the thread that filled it. At most kMaxCurves curves (about
// 2 kB each) a thread; a full cache is emptied.
struct CurveKey {
  std::size_t part;                                   // Component::part's index
  double shape, q, spread, cutoff_hz, taps, rate_hz;  // shape: tau_c or f0
  std::int64_t n_samples;
  friend bool operator==(const CurveKey&, const CurveKey&) = default;
};
struct CachedCurve {
  CurveKey key;
  std::vector<std::int64_t> m;
  std::vector<double> tau, g;
};
constexpr std::size_t kMaxCurves = 4096;

std::size_t curve_hash(const CurveKey& k, const Curve& cv) {
  std::size_t h = k.part;
  const auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 0x100000001b3ULL; };
  for (const double v : {k.shape, k.q, k.spread, k.cutoff_hz, k.taps, k.rate_hz})
    mix(std::bit_cast<std::uint64_t>(v));
  mix(static_cast<std::uint64_t>(k.n_samples));
  mix(cv.m.size());
  if (!cv.m.empty()) mix(static_cast<std::uint64_t>(cv.m.back()));
  return h;
}

}  // namespace

std::vector<double> shaped_curve(const Component& c, const Curve& cv, const Bases& b) {
  const Resonance* r = std::get_if<Resonance>(&c.part);
  const CurveKey key{c.part.index(),
                     r != nullptr ? r->frequency_hz : as<GaussMarkov>(c).tau_c_s,
                     r != nullptr ? r->q : 0.0,
                     r != nullptr ? r->spread_hz : 0.0,
                     b.lowpass.cutoff_hz,
                     b.lowpass.taps,
                     b.rate_hz,
                     cv.n_samples};
  thread_local std::unordered_multimap<std::size_t, CachedCurve> cache;
  const std::size_t h = curve_hash(key, cv);
  const auto [lo, hi] = cache.equal_range(h);
  for (auto it = lo; it != hi; ++it)
    if (it->second.key == key && it->second.m == cv.m && it->second.tau == cv.tau)
      return it->second.g;
  std::vector<double> g = r == nullptr ? markov_curve(1.0, key.shape, cv, b.lowpass, b.rate_hz)
                                       : resonance_curve({1.0, r->frequency_hz, r->q, r->spread_hz},
                                                         cv, b.lowpass, b.rate_hz);
  if (cache.size() >= kMaxCurves) cache.clear();
  cache.emplace(h, CachedCurve{key, cv.m, cv.tau, g});
  return g;
}

}  // namespace allanlot::kernels::diagnose_detail
