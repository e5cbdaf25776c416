// Noise synthesis: see simulate.hpp for the sampling model and the reproducibility guarantee.
#include "kernels/simulate/simulate.hpp"

#include "kernels/powerlaw/theory.hpp"

#include "kernels/common/parallel.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/spectral/fft.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::kernels {

namespace {

using std::numbers::pi;

// Samples per generation block. Fixed (never derived from the thread count) so that the
// sequential carries of the random walk and Gauss-Markov components, which are combined per
// block, round identically for every thread count. Even, so that Box-Muller pairs never
// straddle two blocks; 2^14 doubles is 128 KiB, a block's output stays in L2.
constexpr std::size_t kBlock = std::size_t{1} << 14;

// Counter layout of rng::bits: indices must stay below 2^56; pair index k+1 is used for
// sample k, and random walk uses one pair per sample.
constexpr std::size_t kMaxSamples = std::size_t{1} << 54;

void check_finite_nonneg(double v, const std::string& name) {
  if (!std::isfinite(v) || v < 0)
    throw std::invalid_argument("simulate: " + name + " must be finite and >= 0, got " +
                                std::to_string(v));
}

// dst[i] = standard normal number first + i of a component's sequence, i < count; pairs are
// computed once and both members used.
void fill_normals(std::uint64_t seed, std::uint64_t stream, std::uint32_t comp, std::size_t first,
                  std::size_t count, double* dst) {
  std::size_t i = 0;
  std::size_t j = first;
  if (count == 0) return;
  if (j % 2 == 1) {
    dst[i++] = rng::normal_pair(seed, stream, comp, j / 2).second;
    ++j;
  }
  for (; i + 1 < count; i += 2, j += 2) {
    const auto [a, b] = rng::normal_pair(seed, stream, comp, j / 2);
    dst[i] = a;
    dst[i + 1] = b;
  }
  if (i < count) dst[i] = rng::normal_pair(seed, stream, comp, j / 2).first;
}

// Smallest 7-smooth integer >= n (FFTW has fast codelets for the factors 2, 3, 5, 7).
std::size_t fft_size_at_least(std::size_t n) {
  for (std::size_t p = std::max<std::size_t>(n, 1);; ++p) {
    std::size_t r = p;
    for (std::size_t f : {2u, 3u, 5u, 7u})
      while (r % f == 0)
        r /= f;
    if (r == 1) return p;
  }
}

}  // namespace

void validate(const ChannelSpec& spec) {
  if (!std::isfinite(spec.rate_hz) || spec.rate_hz <= 0)
    throw std::invalid_argument("simulate: rate_hz must be finite and > 0, got " +
                                std::to_string(spec.rate_hz));
  check_finite_nonneg(spec.terms.R, "R");
  check_finite_nonneg(spec.terms.K, "K");
  check_finite_nonneg(spec.terms.B, "B");
  check_finite_nonneg(spec.terms.N, "N");
  check_finite_nonneg(spec.terms.Q, "Q");
  if (!std::isfinite(spec.offset)) throw std::invalid_argument("simulate: offset must be finite");
  check_finite_nonneg(spec.quantum, "quantum");
  check_finite_nonneg(spec.flicker_pm, "flicker_pm");
  try {
    validate_lowpass(spec.lowpass, spec.rate_hz);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("simulate: ") + e.what());
  }
  validate_effects(spec, "simulate");
}

std::vector<double> kasdin_flicker_filter(std::size_t n) {
  std::vector<double> h(n);
  if (n == 0) return h;
  h[0] = 1.0;
  for (std::size_t k = 1; k < n; ++k)
    h[k] = h[k - 1] * (static_cast<double>(k) - 0.5) / static_cast<double>(k);
  return h;
}

// ---------------------------------------------------------------------------------------------

struct SimulationPlan::Impl {
  std::size_t n = 0;
  // Overlap-save geometry: filter length M = n, FFT size P >= M + L - 1, L outputs per block.
  std::size_t M = 0, P = 0, L = 0, n_bins = 0;
  fft::Buffer<double> work;            // 2 n_bins doubles, in-place r2c/c2r
  fft::Buffer<fftw_complex> spectrum;  // DFT of the zero-padded filter
  std::optional<fft::Plan> forward, inverse;
  std::size_t block_hint = 0;

  // Plans and computes the filter spectrum on first use, so that channels without flicker
  // cost no memory.
  void prepare_flicker() {
    if (spectrum) return;
    M = n;
    const std::size_t l_min = block_hint == 0 ? n : std::min(block_hint, n);
    P = fft_size_at_least(M + l_min - 1);
    if (P > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::invalid_argument("simulate: flicker FFT size " + std::to_string(P) +
                                  " exceeds FFTW's int sizes; n_samples is too large");
    L = P - M + 1;
    n_bins = P / 2 + 1;
    work = fft::alloc<double>(2 * n_bins);
    fft::Buffer<fftw_complex> spec = fft::alloc<fftw_complex>(n_bins);
    // fft::Plan (FFTW_ESTIMATE on fft::alloc'ed buffers): the same size always gets the same
    // algorithm and the same rounding, which byte reproducibility needs.
    auto* c = reinterpret_cast<fftw_complex*>(work.get());
    forward.emplace(fft::Plan::r2c(static_cast<int>(P), work.get(), c, "simulate"));
    inverse.emplace(fft::Plan::c2r(static_cast<int>(P), c, work.get(), "simulate"));
    const auto h = kasdin_flicker_filter(M);
    std::copy(h.begin(), h.end(), work.get());
    std::fill(work.get() + M, work.get() + 2 * n_bins, 0.0);
    forward->execute();
    std::memcpy(spec.get(), work.get(), sizeof(fftw_complex) * n_bins);
    spectrum = std::move(spec);
  }

  // out[k] = B sum_{j=0}^{k} h_j g_{k-j}, k < n (linear convolution; g_j = 0 for j < 0).
  // Overlap-save (e.g. Oppenheim & Schafer, Discrete-Time Signal Processing, sec. 8.7.3):
  // block b computes outputs [b L, b L + L) from the P inputs starting at b L - (M - 1); the
  // first M - 1 outputs of the circular convolution are wrapped and discarded.
  void flicker(double B, std::uint64_t seed, std::uint64_t stream, std::span<double> out,
               [[maybe_unused]] int nt, rng::Component component = rng::Component::Flicker) {
    prepare_flicker();
    auto* buf = work.get();
    auto* c = reinterpret_cast<fftw_complex*>(buf);
    const auto comp = static_cast<std::uint32_t>(component);
    const std::size_t n_blocks = (n + L - 1) / L;
    // c2r is unnormalized (FFTW's convention): the round trip multiplies by P. The 1/P and
    // the coefficient B are folded into the spectral product, once per bin.
    const double scale = B / static_cast<double>(P);
    for (std::size_t b = 0; b < n_blocks; ++b) {
      const auto start = static_cast<std::int64_t>(b * L) - static_cast<std::int64_t>(M - 1);
      const auto n_fill = static_cast<std::int64_t>(P);
      const auto kb = static_cast<std::int64_t>(kBlock);
      const auto n_rec = static_cast<std::int64_t>(n);
      const std::int64_t n_chunks = (n_fill + kb - 1) / kb;
      ExceptionCollector ec;
#pragma omp parallel for num_threads(nt) schedule(static)
      for (std::int64_t ch = 0; ch < n_chunks; ++ch) {
        ec.run([&] {
          const std::int64_t i0 = ch * kb;
          const std::int64_t i1 = std::min(n_fill, i0 + kb);
          // Inputs before sample 0 (the pre-record past) and after the record are zero.
          const std::int64_t j0 = std::clamp<std::int64_t>(start + i0, 0, n_rec);
          const std::int64_t j1 = std::clamp<std::int64_t>(start + i1, 0, n_rec);
          std::fill(buf + i0, buf + i1, 0.0);
          if (j1 > j0)
            fill_normals(seed, stream, comp, static_cast<std::size_t>(j0),
                         static_cast<std::size_t>(j1 - j0), buf + (j0 - start));
        });
      }
      ec.rethrow();
      std::fill(buf + P, buf + 2 * n_bins, 0.0);
      forward->execute();
      const auto bins = static_cast<std::int64_t>(n_bins);
      const fftw_complex* H = spectrum.get();
#pragma omp parallel for num_threads(nt) schedule(static)
      for (std::int64_t i = 0; i < bins; ++i) {
        const double re = c[i][0] * H[i][0] - c[i][1] * H[i][1];
        const double im = c[i][0] * H[i][1] + c[i][1] * H[i][0];
        c[i][0] = re * scale;
        c[i][1] = im * scale;
      }
      inverse->execute();
      const std::size_t k0 = b * L;
      const std::size_t k1 = std::min(n, k0 + L);
      std::copy(buf + (M - 1), buf + (M - 1) + (k1 - k0), out.begin() + static_cast<long>(k0));
    }
  }

  // The phase's flicker (ChannelSpec::flicker_pm), differenced: y_k += (x_k - x_{k-1}) / tau0,
  // x_{-1} = 0. Kasdin's sequence of driving variance h_1 / (4 pi) has the one-sided phase PSD
  // h_1 / (4 pi^2 f), i.e. S_y = h_1 f. Nothing without flicker PM.
  void add_flicker_pm(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream,
                      std::span<double> out, int nt) {
    if (!(spec.flicker_pm > 0)) return;
    std::vector<double> x(n);
    flicker(std::sqrt(spec.flicker_pm / (4.0 * pi)), seed, stream, x, nt,
            rng::Component::FlickerPm);
    for (std::size_t k = n; k-- > 0;)
      out[k] += (x[k] - (k > 0 ? x[k - 1] : 0.0)) * spec.rate_hz;
  }
};

SimulationPlan::SimulationPlan(std::size_t n_samples, std::size_t flicker_block)
    : impl_(std::make_unique<Impl>()) {
  if (n_samples == 0) throw std::invalid_argument("simulate: n_samples must be >= 1");
  if (n_samples > kMaxSamples)
    throw std::invalid_argument("simulate: n_samples must be < 2^54, got " +
                                std::to_string(n_samples));
  impl_->n = n_samples;
  impl_->block_hint = flicker_block;
}

SimulationPlan::~SimulationPlan() = default;

std::size_t SimulationPlan::size() const {
  return impl_->n;
}

namespace {

// Passes 2 and 3 of SimulationPlan::run: the random walk's and the Carried effects' block
// start states, combined in block order from each block's local end state (`walk_end`,
// `carried_end`), and their contributions added to every block of `out`.
void add_block_starts(const NoiseTerms& t, const std::vector<CarriedStep>& steps,
                      const std::vector<double>& walk_end, const std::vector<double>& carried_end,
                      std::uint64_t seed, std::uint64_t stream, std::span<double> out,
                      [[maybe_unused]] int nt) {
  const std::size_t n = out.size();
  const std::size_t n_carried = steps.size();
  const std::size_t n_blocks = (n + kBlock - 1) / kBlock;
  const auto blocks = static_cast<std::int64_t>(n_blocks);
  // Pass 2 (sequential, in block order): the true state at each block's start.
  std::vector<double> walk_start(walk_end.size());
  for (std::size_t b = 1; b < walk_end.size(); ++b)
    walk_start[b] = walk_start[b - 1] + walk_end[b - 1];
  std::vector<double> carried_start(n_blocks * n_carried);
  for (std::size_t e = 0; e < n_carried; ++e) {
    // Stationary start: m(0) ~ N(0, sigma^2), from pair 0 of the effect's sequence.
    double m = steps[e].sigma * rng::normal_pair(seed, stream, steps[e].component, 0).first;
    for (std::size_t b = 0; b < n_blocks; ++b) {
      carried_start[b * n_carried + e] = m;
      const std::size_t len = std::min(kBlock, n - b * kBlock);
      m = std::pow(steps[e].phi, static_cast<double>(len)) * m + carried_end[b * n_carried + e];
    }
  }
  // Pass 3 (parallel over blocks): add the start states' contributions, which the recursions
  // propagate linearly: K W_start to every sample, and phi^i m_start into the state at sample i.
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t b = 0; b < blocks; ++b) {
    const std::size_t k0 = static_cast<std::size_t>(b) * kBlock;
    const std::size_t len = std::min(kBlock, n - k0);
    double* y = out.data() + k0;
    if (t.K > 0) {
      const double add = t.K * walk_start[static_cast<std::size_t>(b)];
      for (std::size_t i = 0; i < len; ++i)
        y[i] += add;
    }
    for (std::size_t e = 0; e < n_carried; ++e) {
      const auto& st = steps[e];
      double carry = carried_start[static_cast<std::size_t>(b) * n_carried + e];
      for (std::size_t i = 0; i < len && carry != 0; ++i) {
        y[i] += st.mean_i * carry * st.inv_h;
        carry *= st.phi;
        // Stop once the carry is far below any sample's resolution (and before denormals).
        if (std::abs(carry) < 1e-300) carry = 0;
      }
    }
  }
}

// The Carried effects' per-interval constants (carried_step; an effect that draws nothing has
// none), in kEffectLists order, each with its stream: effect i of a list first_stream + i.
std::vector<CarriedStep> carried_steps(const ChannelSpec& spec, double h) {
  std::vector<CarriedStep> steps;
  for_each_effect_list(spec, [&](const auto& list) {
    using P = EffectProcess<EffectOf<decltype(list)>>;
    if constexpr (P::synthesis == Synthesis::Carried)
      for (std::size_t i = 0; i < list.size(); ++i)
        if (auto st = carried_step(list[i], h)) {
          st->component = P::first_stream + static_cast<std::uint32_t>(i);
          steps.push_back(*st);
        }
  });
  return steps;
}

// The Block effects over the block y of the record (its first sample `first`), in kEffectLists
// order, each effect over the whole block in turn.
void add_block_effects(const ChannelSpec& spec, std::size_t first, std::span<double> y) {
  for_each_effect_list(spec, [&](const auto& list) {
    if constexpr (EffectProcess<EffectOf<decltype(list)>>::synthesis == Synthesis::Block)
      for (const auto& e : list)
        add_effect_block(e, spec.rate_hz, first, y);
  });
}

// Pass 1 of the Carried effects over the block y starting at sample k0: each recursion started
// at 0 (the true start state is added in passes 2 and 3), its end state into end[e]. Sample k
// draws pair k + 1 of the effect's stream (pair 0 is the stationary start).
void add_carried_local(const std::vector<CarriedStep>& steps, std::uint64_t seed,
                       std::uint64_t stream, std::size_t k0, std::span<double> y, double* end) {
  for (std::size_t e = 0; e < steps.size(); ++e) {
    const auto& st = steps[e];
    double m = 0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      const auto [z1, z2] = rng::normal_pair(seed, stream, st.component, k0 + i + 1);
      const double integral = st.mean_i * m + st.c * z1 + st.d * z2;
      y[i] += integral * st.inv_h;
      m = st.phi * m + st.s_m * z1;
    }
    end[e] = m;
  }
}

// The Record effects over the whole record, in kEffectLists order; effect i of a list draws
// stream first_stream + i.
void add_record_effects(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream,
                        std::span<double> out) {
  for_each_effect_list(spec, [&](const auto& list) {
    using P = EffectProcess<EffectOf<decltype(list)>>;
    if constexpr (P::synthesis == Synthesis::Record)
      for (std::size_t i = 0; i < list.size(); ++i)
        add_effect_record(list[i], spec.rate_hz, seed, stream,
                          P::first_stream + static_cast<std::uint32_t>(i), out);
  });
}

}  // namespace

void SimulationPlan::run(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream,
                         std::span<double> out, int nthreads) {
  validate(spec);
  const std::size_t n = impl_->n;
  if (out.size() != n)
    throw std::invalid_argument("simulate: out has " + std::to_string(out.size()) +
                                " samples, the plan " + std::to_string(n));
  const int nt = resolve_threads(nthreads);
  const double h = 1.0 / spec.rate_hz;
  const auto& t = spec.terms;

  if (t.B > 0)
    impl_->flicker(t.B, seed, stream, out, nt);
  else
    std::fill(out.begin(), out.end(), 0.0);

  const std::vector<CarriedStep> steps = carried_steps(spec, h);
  const std::size_t n_carried = steps.size();
  const std::size_t n_blocks = (n + kBlock - 1) / kBlock;
  // End states of each block's local (zero-start) recursions, combined in block order below.
  std::vector<double> walk_end(t.K > 0 ? n_blocks : 0);
  std::vector<double> carried_end(n_blocks * n_carried);

  const double white_sd = t.N * std::sqrt(spec.rate_hz);  // N^2/tau0: avar N^2/tau at m = 1
  const double sqrt_h = std::sqrt(h);
  const double bridge_sd = std::sqrt(h / 12.0);  // mean of a Brownian bridge over h
  const double q_scale = t.Q * spec.rate_hz;     // (q_{k+1} - q_k) / tau0, q ~ N(0, Q^2)
  const auto white_comp = static_cast<std::uint32_t>(rng::Component::White);
  const auto walk_comp = static_cast<std::uint32_t>(rng::Component::RandomWalk);
  const auto quant_comp = static_cast<std::uint32_t>(rng::Component::Quantization);

  ExceptionCollector ec;
  const auto blocks = static_cast<std::int64_t>(n_blocks);
#pragma omp parallel num_threads(nt)
  {
    std::vector<double> g;
#pragma omp for schedule(static)
    for (std::int64_t b = 0; b < blocks; ++b) {
      ec.run([&] {
        if (g.empty()) g.resize(kBlock + 2);
        const std::size_t k0 = static_cast<std::size_t>(b) * kBlock;
        const std::size_t len = std::min(kBlock, n - k0);
        double* y = out.data() + k0;
        for (std::size_t i = 0; i < len; ++i)
          y[i] += spec.offset;
        if (t.N > 0) {
          fill_normals(seed, stream, white_comp, k0, len, g.data());
          for (std::size_t i = 0; i < len; ++i)
            y[i] += white_sd * g[i];
        }
        if (t.K > 0) {
          // Exact sample means of a Wiener process K W(t), W(0) = 0: endpoint increments
          // sqrt(h) g1 plus the independent mean of the Brownian bridge, so that averages over
          // m samples are the continuous averages over tau and avar = K^2 tau / 3 at every m.
          double w = 0;
          for (std::size_t i = 0; i < len; ++i) {
            const auto [g1, g2] = rng::normal_pair(seed, stream, walk_comp, k0 + i);
            const double w_next = w + sqrt_h * g1;
            y[i] += t.K * (0.5 * (w + w_next) + bridge_sd * g2);
            w = w_next;
          }
          walk_end[static_cast<std::size_t>(b)] = w;
        }
        if (t.R > 0)
          for (std::size_t i = 0; i < len; ++i)
            y[i] += t.R * (static_cast<double>(k0 + i) + 0.5) * h;
        if (t.Q > 0) {
          fill_normals(seed, stream, quant_comp, k0, len + 1, g.data());
          for (std::size_t i = 0; i < len; ++i)
            y[i] += q_scale * (g[i + 1] - g[i]);
        }
        add_block_effects(spec, k0, std::span<double>(y, len));
        add_carried_local(steps, seed, stream, k0, std::span<double>(y, len),
                          carried_end.data() + static_cast<std::size_t>(b) * n_carried);
      });
    }
  }
  ec.rethrow();
  if (t.K > 0 || n_carried > 0)
    add_block_starts(t, steps, walk_end, carried_end, seed, stream, out, nt);
  impl_->add_flicker_pm(spec, seed, stream, out, nt);
  add_record_effects(spec, seed, stream, out);
  apply_lowpass(spec.lowpass, spec.rate_hz, out);
  if (spec.quantum > 0)
    for (double& y : out)
      y = spec.quantum * std::nearbyint(y / spec.quantum);
}

void simulate_channel(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream,
                      std::span<double> out, int nthreads) {
  validate(spec);
  if (out.empty()) throw std::invalid_argument("simulate: out must have at least 1 sample");
  SimulationPlan plan(out.size());
  plan.run(spec, seed, stream, out, nthreads);
}

// ---------------------------------------------------------------------------------------------
// Theory

namespace {

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's iteration on P_n (Abramowitz &
// Stegun 25.4.29; the initial guesses cos(pi (i - 1/4) / (n + 1/2)) converge for every root).
struct GaussLegendre {
  static constexpr int kN = 16;
  double x[kN], w[kN];
  GaussLegendre() {
    for (int i = 0; i < kN; ++i) {
      double z = std::cos(pi * (i + 0.75) / (kN + 0.5));
      double dp = 1;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= kN; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = kN * (z * p1 - p0) / (z * z - 1);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[i] = z;
      w[i] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};

}  // namespace

double flicker_avar_factor(std::int64_t m) {
  if (m < 1)
    throw std::invalid_argument("flicker_avar_factor: m must be >= 1, got " + std::to_string(m));
  if (m > 4096) return 1.0;
  static const GaussLegendre gl;
  // sin^4(m x) has period pi/m: 2m panels over [0, pi/2] each span half a period, on which the
  // integrand is smooth (1/sin^3 x is analytic on (0, pi/2], and sin^4(mx)/sin^3 x ~ m^4 x at
  // 0), so 16 nodes per panel integrate it to ~1e-14.
  const double md = static_cast<double>(m);
  const std::int64_t panels = 2 * m;
  const double width = (pi / 2) / static_cast<double>(panels);
  double sum = 0;
  for (std::int64_t p = 0; p < panels; ++p) {
    const double mid = (static_cast<double>(p) + 0.5) * width;
    double s = 0;
    for (int i = 0; i < GaussLegendre::kN; ++i) {
      const double x = mid + 0.5 * width * gl.x[i];
      const double sm = std::sin(md * x);
      const double sx = std::sin(x);
      s += gl.w[i] * (sm * sm * sm * sm) / (sx * sx * sx);
    }
    sum += 0.5 * width * s;
  }
  return sum / (md * md) / std::numbers::ln2;
}

double model_avar(const ChannelSpec& spec, double tau_s) {
  if (!(tau_s > 0) || !std::isfinite(tau_s))
    throw std::invalid_argument("model_avar: tau_s must be finite and > 0, got " +
                                std::to_string(tau_s));
  const auto& t = spec.terms;
  const double tau = tau_s;
  double v = t.R * t.R * tau * tau / 2 + t.K * t.K * tau / 3 +
             t.B * t.B * 2 * std::numbers::ln2 / pi + t.N * t.N / tau + 3 * t.Q * t.Q / (tau * tau);
  for_each_effect_list(spec, [&](const auto& list) {
    for (const auto& e : list)
      v += effect_avar(e, spec.rate_hz, tau);
  });
  // The output's rounding: white of variance quantum^2 / 12 per sample, so quantum^2 / (12 m).
  v += spec.quantum * spec.quantum / (12.0 * tau * spec.rate_hz);
  if (spec.flicker_pm > 0) v += spec.flicker_pm * powerlaw::avar_per_h(1, tau, 1.0 / spec.rate_hz);
  return v;
}

double model_avar_sampled(const ChannelSpec& spec, std::int64_t m, std::int64_t n_samples) {
  if (m < 1) throw std::invalid_argument("model_avar_sampled: m must be >= 1");
  if (!std::isfinite(spec.rate_hz) || spec.rate_hz <= 0)
    throw std::invalid_argument("model_avar_sampled: rate_hz must be finite and > 0");
  const double flicker = spec.terms.B * spec.terms.B * 2 * std::numbers::ln2 / pi;
  const double tau = static_cast<double>(m) / spec.rate_hz;
  double v = model_avar(spec, tau) + flicker * (flicker_avar_factor(m) - 1.0);
  // Each effect's share that the record's length sets (the steps'), then under the filter
  // what it changes in each share, in kEffectLists order.
  if (n_samples > 0)
    for_each_effect_list(spec, [&](const auto& list) {
      using E = EffectOf<decltype(list)>;
      v = plus_record_avar(v, std::span<const E>(list), spec.rate_hz, m, n_samples);
    });
  if (!spec.lowpass.active()) return v;
  const Lowpass& lp = spec.lowpass;
  const auto& t = spec.terms;
  v += t.N * t.N / tau * (lowpass_white_fm_factor(lp, spec.rate_hz, m) - 1.0);
  v += 3 * t.Q * t.Q / (tau * tau) * (lowpass_white_pm_factor(lp, spec.rate_hz, m) - 1.0);
  const FilterAt at(lp, spec.rate_hz, m);
  for_each_effect_list(spec, [&](const auto& list) {
    for (const auto& e : list)
      v += filter_change_avar(e, at);
  });
  return v;
}

double model_psd_one_sided(const ChannelSpec& spec, double f_hz) {
  return model_psd_one_sided(spec, std::span(&f_hz, 1)).front();
}

std::vector<double> model_psd_one_sided(const ChannelSpec& spec, std::span<const double> f_hz) {
  const auto& t = spec.terms;
  std::vector<double> out(f_hz.size());
  for (std::size_t i = 0; i < f_hz.size(); ++i) {
    const double f = f_hz[i];
    if (!(f > 0) || !std::isfinite(f))
      throw std::invalid_argument("model_psd_one_sided: f_hz must be finite and > 0, got " +
                                  std::to_string(f));
    const double w = 2 * pi * f;
    out[i] = t.K * t.K / (2 * pi * pi * f * f) + t.B * t.B / (pi * f) + 2 * t.N * t.N +
             2 * w * w * t.Q * t.Q / spec.rate_hz +
             spec.quantum * spec.quantum / (6.0 * spec.rate_hz) + spec.flicker_pm * f;
  }
  // Each effect's density added at every frequency in turn: per frequency the same sums, in the
  // same order, as one frequency at a time.
  for_each_effect_list(spec, [&](const auto& list) {
    for (const auto& e : list)
      add_effect_psd(e, spec.rate_hz, f_hz, out);
  });
  return out;
}

}  // namespace allanlot::kernels
