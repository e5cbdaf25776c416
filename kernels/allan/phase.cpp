#include "kernels/allan/phase.hpp"

#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

// Fixed chunk length of the parallel prefix sum. It must not depend on the thread count:
// the chunk boundaries decide the rounding, and fixing them makes x bit-identical for any
// number of threads (docs/development.md "Threads and determinism": prefix sums are built in
// fixed-size chunks).
constexpr std::int64_t kChunk = 1 << 16;

void check_rate_hz(double rate_hz) {
  if (!(std::isfinite(rate_hz) && rate_hz > 0.0)) {
    std::ostringstream msg;
    msg << "rate_hz must be finite and > 0, got " << rate_hz;
    throw std::invalid_argument(msg.str());
  }
}

// Integrates n increments given by inc(k) (NaN = missing) into n+1 phase points scaled by
// `scale`. Shared by the rate and phase paths so that both see the same rounding.
template <class Increment>
PhaseData integrate(std::int64_t n, Increment inc, double scale, int nthreads) {
  const std::int64_t nchunks = (n + kChunk - 1) / kChunk;
  std::vector<long double> chunk_sum(static_cast<std::size_t>(nchunks), 0.0L);
  std::vector<std::int64_t> chunk_valid(static_cast<std::size_t>(nchunks), 0);
  std::vector<std::int64_t> chunk_inf(static_cast<std::size_t>(nchunks), 0);
  const int nt = resolve_threads(nthreads);

  // Pass 1: per-chunk sums of the valid increments, for the mean.
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    long double s = 0.0L;
    std::int64_t valid = 0, inf = 0;
    const std::int64_t end = std::min(n, (c + 1) * kChunk);
    for (std::int64_t k = c * kChunk; k < end; ++k) {
      const long double v = inc(k);
      if (std::isnan(v)) continue;
      if (std::isinf(v)) {
        ++inf;
        continue;
      }
      s += v;
      ++valid;
    }
    chunk_sum[static_cast<std::size_t>(c)] = s;
    chunk_valid[static_cast<std::size_t>(c)] = valid;
    chunk_inf[static_cast<std::size_t>(c)] = inf;
  }
  long double total = 0.0L;
  std::int64_t valid = 0, inf = 0;
  for (std::int64_t c = 0; c < nchunks; ++c) {
    total += chunk_sum[static_cast<std::size_t>(c)];
    valid += chunk_valid[static_cast<std::size_t>(c)];
    inf += chunk_inf[static_cast<std::size_t>(c)];
  }
  if (inf > 0)
    throw std::invalid_argument("samples contain " + std::to_string(inf) +
                                " infinite value(s); only NaN may mark a gap");
  if (valid == 0) throw std::invalid_argument("no valid (non-NaN) sample");
  const long double mean = total / static_cast<long double>(valid);

  PhaseData out;
  out.tau0_s = 1.0;  // set by the caller
  out.n_gaps = n - valid;
  out.mean_rate = static_cast<double>(mean);
  out.x.resize(static_cast<std::size_t>(n + 1));  // every element is written below
  out.x[0] = 0.0;
  if (out.n_gaps > 0) out.gaps.assign(static_cast<std::size_t>(n + 1), 0);

  // Pass 2: per-chunk sums of the mean-removed increments (exclusive scan combined in index
  // order), then pass 3 writes each chunk's running sum from its offset. Each element is
  // written by one thread in a fixed order.
  std::vector<long double> offset(static_cast<std::size_t>(nchunks) + 1, 0.0L);
  std::vector<std::int64_t> gap_offset(static_cast<std::size_t>(nchunks) + 1, 0);
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    long double s = 0.0L;
    const std::int64_t end = std::min(n, (c + 1) * kChunk);
    for (std::int64_t k = c * kChunk; k < end; ++k) {
      const long double v = inc(k);
      if (!std::isnan(v)) s += v - mean;
    }
    chunk_sum[static_cast<std::size_t>(c)] = s;
  }
  for (std::int64_t c = 0; c < nchunks; ++c) {
    offset[static_cast<std::size_t>(c) + 1] =
        offset[static_cast<std::size_t>(c)] + chunk_sum[static_cast<std::size_t>(c)];
    gap_offset[static_cast<std::size_t>(c) + 1] =
        gap_offset[static_cast<std::size_t>(c)] +
        (std::min(n, (c + 1) * kChunk) - c * kChunk - chunk_valid[static_cast<std::size_t>(c)]);
  }
  const long double lscale = scale;
  double* x = out.x.data();
  std::int64_t* g = out.gaps.empty() ? nullptr : out.gaps.data();
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    long double s = offset[static_cast<std::size_t>(c)];
    std::int64_t gs = gap_offset[static_cast<std::size_t>(c)];
    const std::int64_t end = std::min(n, (c + 1) * kChunk);
    for (std::int64_t k = c * kChunk; k < end; ++k) {
      const long double v = inc(k);
      if (std::isnan(v)) {
        ++gs;
      } else {
        s += v - mean;
      }
      x[k + 1] = static_cast<double>(s * lscale);
      if (g) g[k + 1] = gs;
    }
  }
  return out;
}

}  // namespace

PhaseData phase_from_rate(std::span<const double> rate, double rate_hz, int nthreads) {
  check_rate_hz(rate_hz);
  if (rate.size() < 2)
    throw std::invalid_argument("need at least 2 rate samples, got " + std::to_string(rate.size()));
  const double* y = rate.data();
  PhaseData p = integrate(
      static_cast<std::int64_t>(rate.size()), [y](std::int64_t k) { return (long double)y[k]; },
      1.0 / rate_hz, nthreads);
  p.tau0_s = 1.0 / rate_hz;
  return p;
}

PhaseData phase_from_phase(std::span<const double> phase, double rate_hz, int nthreads) {
  check_rate_hz(rate_hz);
  if (phase.size() < 3)
    throw std::invalid_argument("need at least 3 phase samples, got " +
                                std::to_string(phase.size()));
  const double* xin = phase.data();
  // Increments in phase units per sample; the differences are exact in long double for
  // doubles of similar magnitude. Scale 1: x is rebuilt in the input's own units.
  PhaseData p = integrate(
      static_cast<std::int64_t>(phase.size()) - 1,
      [xin](std::int64_t k) { return (long double)xin[k + 1] - (long double)xin[k]; }, 1.0,
      nthreads);
  p.tau0_s = 1.0 / rate_hz;
  p.mean_rate *= rate_hz;  // phase units per second
  // n_gaps counts missing increments here; report missing phase points instead.
  std::int64_t missing = 0;
  for (const double v : phase)
    if (std::isnan(v)) ++missing;
  p.n_gaps = missing;
  return p;
}

PhaseData make_phase(std::span<const double> samples, DataType type, double rate_hz, int nthreads) {
  return type == DataType::Rate ? phase_from_rate(samples, rate_hz, nthreads)
                                : phase_from_phase(samples, rate_hz, nthreads);
}

}  // namespace allanlot::kernels
