// Shared by the tests of the further statistics (test_tie.cpp, test_theo.cpp,
// test_total_family.cpp, test_parabolic.cpp): PHASE.DAT, seeded random phase, the row-by-row
// comparison with a Stable32 table, and the thread-invariance check.
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "reference/stable32.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace allanlot::test {

using MList = std::vector<std::int64_t>;

// Stable32 prints 5 significant digits: a correct value is within half a unit of the 5th
// digit (5e-5 relative); 1e-4 leaves room for the printed rounding (as test_allan_family.cpp).
inline constexpr double kStable32Rel = 1e-4;

inline kernels::PhaseData phase_dat() {
  const auto x = read_column("stable32/phasedat/PHASE.DAT");
  EXPECT_EQ(x.size(), 1001u);
  return kernels::phase_from_phase(x, 1.0, 1);
}

/// White phase, white rate and random-walk rate around a frequency offset `rate` per sample
/// and a phase offset `offset`: every power law, and the offsets that the time-error
/// statistics must keep and the others must cancel.
inline std::vector<double> random_phase(std::size_t n, unsigned seed, double offset = 5.0,
                                        double rate = 0.3) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double phase = offset, walk = 0.0;
  for (auto& v : x) {
    walk += 0.01 * g(rng);
    phase += rate + g(rng) + walk;
    v = phase + 0.5 * g(rng);
  }
  return x;
}

/// How many rows of a table agreed.
struct TableMatch {
  int rows = 0;           // rows compared
  int rows_within = 0;    // deviation within kStable32Rel, m, tau and # equal
  int bounds = 0;         // rows with printed bounds
  int bounds_within = 0;  // both bounds within kStable32Rel
  int alpha_equal = 0;    // rows with printed bounds whose identified alpha is Stable32's
};

/// Compares statistic s on p at the table's own m column with every row of `file` (including
/// the rows commented out in the AllanTools copy): m, tau and # exactly (# to Stable32's
/// printed digits when it prints it as %.4e), the deviation within kStable32Rel. The deviation
/// is multiplied by `scale` first (a documented bias factor; 1 for none). With `intervals`
/// the confidence intervals are computed (add_confidence) and the bounds are counted, not
/// asserted: the caller states which must match.
inline TableMatch compare_with_table(kernels::Stat s, const kernels::PhaseData& p,
                                     const std::string& file, bool intervals, double scale = 1.0) {
  SCOPED_TRACE(file);
  const auto rows = read_stable32_every_row(file);
  EXPECT_FALSE(rows.empty());
  MList ms;
  for (const auto& r : rows)
    ms.push_back(r.m);
  auto res = kernels::compute(s, p, ms, 2);
  if (intervals) kernels::add_confidence(s, p, res, kernels::kDefaultConfidence, 2);
  TableMatch out;
  EXPECT_EQ(res.size(), rows.size());
  if (res.size() != rows.size()) return out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    ++out.rows;
    const double n_digits = r.n >= 100000 ? 1e-4 * static_cast<double>(r.n) : 0.5;
    const bool ok = res.m[i] == r.m && std::abs(res.tau_s[i] - r.tau) <= 1e-9 * r.tau &&
                    std::abs(static_cast<double>(res.n[i] - r.n)) <= n_digits &&
                    std::abs(scale * res.dev[i] / r.sigma - 1.0) <= kStable32Rel;
    EXPECT_TRUE(ok) << "m=" << r.m << " n " << res.n[i] << " vs " << r.n << " dev "
                    << scale * res.dev[i] << " vs " << r.sigma;
    out.rows_within += ok ? 1 : 0;
    if (intervals && r.min_sigma > 0) {
      ++out.bounds;
      const bool b = std::abs(scale * res.dev_lo[i] / r.min_sigma - 1.0) <= kStable32Rel &&
                     std::abs(scale * res.dev_hi[i] / r.max_sigma - 1.0) <= kStable32Rel;
      out.bounds_within += b ? 1 : 0;
      out.alpha_equal += res.alpha[i] == r.alpha ? 1 : 0;
    }
  }
  return out;
}

/// Bit-identical results for 1, 2 and 7 threads (docs/development.md "Tests, three ways").
inline void expect_thread_invariant(kernels::Stat s, const kernels::PhaseData& p, const MList& ms) {
  const auto r1 = kernels::compute(s, p, ms, 1);
  ASSERT_GT(r1.size(), 3u) << kernels::stat_name(s);
  for (const int nt : {2, 7}) {
    const auto rn = kernels::compute(s, p, ms, nt);
    EXPECT_EQ(r1.m, rn.m) << kernels::stat_name(s) << " " << nt << " threads";
    EXPECT_EQ(r1.n, rn.n) << kernels::stat_name(s) << " " << nt << " threads";
    EXPECT_EQ(r1.dev, rn.dev) << kernels::stat_name(s) << " " << nt << " threads";
  }
}

}  // namespace allanlot::test
