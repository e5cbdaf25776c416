// The coverage study of the N-cornered hat's intervals
// (docs/validation/2026-11-28-hat-and-masks.md; not a benchmark): four independent clocks of white
// FM at different levels (sigma_y(1 s) = 1, 1.5, 2, 3), the six pairs formed as their differences,
// REPS records of N points each; per clock and tau, the share of records whose interval holds the
// clock's true Allan deviation, at the confidence levels 0.683 and 0.95, and the mean of dev /
// truth.
//
//   study_hat [REPS] [N]   (default 400 records of 4096 points)
//
// Seeded: every run prints the same table.
#include "kernels/allan/phase.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/hat.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

int main(int argc, char** argv) {
  using namespace allanlot;
  const int reps = argc > 1 ? std::atoi(argv[1]) : 400;
  const std::size_t n = argc > 2 ? static_cast<std::size_t>(std::atoll(argv[2])) : 4096;
  constexpr std::size_t kClocks = 4;
  const double level[kClocks] = {1.0, 1.5, 2.0, 3.0};
  const std::vector<std::int64_t> ms = {1, 4, 16, 64};
  const double levels[2] = {0.683, 0.95};
  // in[c][clock][tau]: records whose interval at level c holds the truth.
  std::vector<std::vector<std::vector<int>>> in(
      2, std::vector<std::vector<int>>(kClocks, std::vector<int>(ms.size(), 0)));
  std::vector<std::vector<double>> ratio(kClocks, std::vector<double>(ms.size(), 0.0));
  for (int r = 0; r < reps; ++r) {
    std::vector<std::vector<double>> y(kClocks, std::vector<double>(n));
    for (std::size_t k = 0; k < kClocks; ++k) {
      kernels::ChannelSpec spec;
      spec.terms.N = level[k];
      kernels::simulate_channel(spec, 7 + static_cast<std::uint64_t>(r), k, y[k], 1);
    }
    std::vector<kernels::PhaseData> pairs;
    for (std::size_t i = 0; i < kClocks; ++i)
      for (std::size_t j = i + 1; j < kClocks; ++j) {
        std::vector<double> d(n);
        for (std::size_t t = 0; t < n; ++t)
          d[t] = y[i][t] - y[j][t];
        pairs.push_back(kernels::phase_from_rate(d, 1.0, 1));
      }
    for (int c = 0; c < 2; ++c) {
      const auto h = kernels::n_cornered_hat(pairs, kClocks, ms, levels[c], 1);
      for (std::size_t k = 0; k < kClocks; ++k)
        for (std::size_t i = 0; i < ms.size() && i < h.clock[k].size(); ++i) {
          const double truth = level[k] / std::sqrt(static_cast<double>(ms[i]));
          in[static_cast<std::size_t>(c)][k][i] +=
              h.clock[k].dev_lo[i] <= truth && truth <= h.clock[k].dev_hi[i];
          if (c == 0) ratio[k][i] += h.clock[k].dev[i] / truth / reps;
        }
    }
  }
  std::printf("N-cornered hat, 4 white-FM clocks (sigma_y(1 s) = 1, 1.5, 2, 3), %d records of "
              "%zu points\n",
              reps, n);
  std::printf("clock  tau(s)  coverage@0.683  coverage@0.95  mean dev/truth\n");
  for (std::size_t k = 0; k < kClocks; ++k)
    for (std::size_t i = 0; i < ms.size(); ++i)
      std::printf("%5c  %6lld  %14.3f  %13.3f  %14.3f\n", static_cast<char>('A' + k),
                  static_cast<long long>(ms[i]), in[0][k][i] / static_cast<double>(reps),
                  in[1][k][i] / static_cast<double>(reps), ratio[k][i]);
  std::printf("binomial sd of a coverage: %.3f at 0.683, %.3f at 0.95\n",
              std::sqrt(0.683 * 0.317 / reps), std::sqrt(0.95 * 0.05 / reps));
  return 0;
}
