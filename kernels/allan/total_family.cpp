#include "kernels/allan/total_family.hpp"

#include "kernels/allan/detail/chunked.hpp"
#include "kernels/allan/detail/sweep.hpp"
#include "kernels/allan/hadamard.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

// Work per OpenMP item: about 2^21 term evaluations (a window costs ~18m of them).
constexpr std::int64_t kWorkPerChunk = std::int64_t{1} << 21;

// Per-thread scratch of one window: its prefix sums (3m + 1) and the reflected prefix sums
// (9m + 1).
struct Scratch {
  std::vector<double> pw, e;
  explicit Scratch(std::int64_t m)
      : pw(static_cast<std::size_t>(3 * m + 1)), e(static_cast<std::size_t>(9 * m + 1)) {}
};

// Mean of the 6m squared z_j of one window (total_family.hpp) from its prefix sums
// pw[t] = sum_{i<t} w_i, t = 0 .. L = 3m.
//
// The half-average slope (SP1065 p. 25) and the window mean come from pw in O(1). With q the
// prefix sums of the detrended, mean-free window, the reflected sequence's prefix sums are
// E(s) = -q(-s) left of the window, q(s) on it and 2 q(L) - q(2L - s) right of it (uninverted
// even reflection), and m z_j = -E(j) + 3 E(j+m) - 3 E(j+2m) + E(j+3m): the third difference of
// E at lag m, i.e. the second difference of the m-sums. Removing the mean adds c s to every E,
// which the third difference cancels; it keeps E of the size of the noise, not of the offset.
double reflected_mean_square(Scratch& sc, std::int64_t m) {
  const std::int64_t L = 3 * m, h = L / 2;
  const double* pw = sc.pw.data();
  const long double mean1 = static_cast<long double>(pw[h]) / h;
  const long double mean2 = static_cast<long double>(pw[L] - pw[L - h]) / h;
  const long double slope = (mean2 - mean1) / static_cast<long double>(L - h);
  const long double c = static_cast<long double>(pw[L]) / L;
  const long double tc = 0.5L * static_cast<long double>(L - 1);
  double* e = sc.e.data() + L;  // e[s] for s = -L .. 2L
  for (std::int64_t t = 0; t <= L; ++t) {
    const auto lt = static_cast<long double>(t);
    e[t] = static_cast<double>(pw[t] - c * lt - slope * (0.5L * lt * (lt - 1) - tc * lt));
  }
  for (std::int64_t s = 1; s <= L; ++s) {
    e[-s] = -e[s];
    e[L + s] = 2.0 * e[L] - e[L - s];
  }
  double sum = 0.0;
  const double inv_m = 1.0 / static_cast<double>(m);
  for (std::int64_t j = -L; j < L; ++j) {
    const double z = ((e[j + 3 * m] - e[j]) - 3.0 * (e[j + 2 * m] - e[j + m])) * inv_m;
    sum += z * z;
  }
  return sum / static_cast<double>(6 * m);
}

void refuse_gaps(const char* name, const PhaseData& p) {
  if (p.has_gaps())
    throw std::invalid_argument(std::string(name) + ": cannot run on gapped data (" +
                                std::to_string(p.n_gaps) +
                                " missing samples): its reflected windows are undefined across a "
                                "gap; fill the gaps first");
}

// Sum over the windows of reflected_mean_square, per m, for windows n = 0 .. windows(m) - 1
// whose prefix sums `fill(n, m, pw)` writes. Chunked and folded in window order.
template <class Windows, class Fill>
std::vector<long double> window_sums(std::span<const std::int64_t> m_list, int nthreads,
                                     Windows windows, Fill fill) {
  const auto chunks = detail::make_chunks(m_list, windows, [](std::int64_t m) {
    // At least 64 windows, so that the scratch of a large m is not allocated per window.
    return std::max<std::int64_t>(64, kWorkPerChunk / (18 * m));
  });
  return detail::run_chunks<long double>(
      m_list, chunks, nthreads,
      [&](std::int64_t m, std::int64_t b, std::int64_t e) {
        Scratch sc(m);
        long double s = 0.0L;
        for (std::int64_t n = b; n < e; ++n) {
          fill(n, m, sc.pw.data());
          s += reflected_mean_square(sc, m);
        }
        return s;
      },
      [](long double& acc, const long double& v) { acc += v; });
}

StatResult rows(const PhaseData& p, std::span<const std::int64_t> m_list,
                const std::vector<long double>& sums,
                std::int64_t (*count)(std::int64_t, std::int64_t), long double norm_tau2,
                bool tau_squared) {
  StatResult out;
  const std::int64_t n = p.n_points();
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    const std::int64_t m = m_list[j], M = count(n, m);
    if (M < 1) continue;
    const long double tau = static_cast<long double>(m) * p.tau0_s;
    const long double scale = tau_squared ? norm_tau2 * tau * tau : norm_tau2;
    out.m.push_back(m);
    out.tau_s.push_back(static_cast<double>(m) * p.tau0_s);
    out.n.push_back(M);
    out.dev.push_back(static_cast<double>(std::sqrt(sums[j] / (scale * M))));
  }
  return out;
}

std::int64_t mtot_windows(std::int64_t n, std::int64_t m) {
  return std::max<std::int64_t>(0, n - 3 * m + 1);
}
std::int64_t htot_windows(std::int64_t n, std::int64_t m) {
  return std::max<std::int64_t>(0, n - 3 * m);
}

}  // namespace

StatResult mtotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("mtotdev", m_list);
  refuse_gaps("mtotdev", p);
  const std::int64_t n = p.n_points();
  const double* x = p.x.data();
  // The window's own prefix sums, of x - x_n (window-local: the offset of the record never
  // enters), accumulated in long double.
  const auto sums = window_sums(
      m_list, nthreads, [n](std::int64_t m) { return mtot_windows(n, m); },
      [x](std::int64_t w, std::int64_t m, double* pw) {
        long double s = 0.0L;
        const double ref = x[w];
        pw[0] = 0.0;
        for (std::int64_t t = 0; t < 3 * m; ++t) {
          s += x[w + t] - ref;
          pw[t + 1] = static_cast<double>(s);
        }
      });
  return rows(p, m_list, sums, mtot_windows, 2.0L, true);
}

StatResult ttotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  StatResult r = mtotdev(p, m_list, nthreads);
  for (std::size_t i = 0; i < r.size(); ++i)
    r.dev[i] *= r.tau_s[i] / std::sqrt(3.0);
  return r;
}

StatResult htotdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("htotdev", m_list);
  refuse_gaps("htotdev", p);
  const std::int64_t n = p.n_points();
  const double* x = p.x.data();
  const double tau0 = p.tau0_s;
  // m = 1 is the overlapping Hadamard deviation (SP1065 p. 27); the others use the windows.
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : m_list)
    if (m != 1) ms.push_back(m);
  // The prefix sums of the frequency averages are phase differences: no accumulation at all.
  const auto sums = window_sums(
      ms, nthreads, [n](std::int64_t m) { return htot_windows(n, m); },
      [x, tau0](std::int64_t w, std::int64_t m, double* pw) {
        for (std::int64_t t = 0; t <= 3 * m; ++t)
          pw[t] = (x[w + t] - x[w]) / tau0;
      });
  const StatResult windows = rows(p, ms, sums, htot_windows, 6.0L, false);
  const std::int64_t one[] = {1};
  const StatResult oh = ms.size() < m_list.size() ? ohdev(p, one, nthreads) : StatResult{};
  StatResult out;  // the rows in the order of m_list
  std::size_t k = 0;
  for (const std::int64_t m : m_list) {
    const bool first = m == 1;
    if (first ? oh.size() == 0 : (k >= windows.size() || windows.m[k] != m)) continue;
    const StatResult& src = first ? oh : windows;
    const std::size_t i = first ? 0 : k++;
    out.m.push_back(src.m[i]);
    out.tau_s.push_back(src.tau_s[i]);
    out.dev.push_back(src.dev[i]);
    out.n.push_back(src.n[i]);
  }
  return out;
}

}  // namespace allanlot::kernels
