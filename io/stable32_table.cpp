#include "io/stable32_table.hpp"

#include "kernels/allan/stats.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace allanlot::io {
namespace {

// Stable32 1.60's sigma type, column titles and row layout of each statistic are facts of the
// statistic (kernels/allan/stats.hpp StatInfo); a name allanlot does not compute has none.
const kernels::StatInfo& info_of(const std::string& stat) {
  const auto s = kernels::parse_stat(stat);
  if (!s) throw std::invalid_argument("stable32_table: no statistic '" + stat + "'");
  return kernels::stat_info(*s);
}

// Stable32 prints 5 significant digits ("%.4e"); a value that is not a number is printed as
// 0, which is what Stable32 shows for a quantity it did not compute.
std::string e4(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4e", std::isfinite(v) ? v : 0.0);
  return buf;
}

// A count in e4's form, its halves rounded up as Stable32 does (Thêo1's "#" 102245 prints
// 1.0225e+05 in phase_dat_theo1.txt, where printf's round-half-even gives 1.0224e+05).
std::string e4_count(long long n) {
  if (n < 100000) return e4(static_cast<double>(n));  // exact in 5 digits
  int e = 0;
  unsigned long long div = 1;
  for (long long t = n; t >= 100000; t /= 10, ++e)
    div *= 10;
  unsigned long long q = (static_cast<unsigned long long>(n) + div / 2) / div;
  e += 4;
  if (q >= 100000) {  // 9.99995e+05 -> 1.0000e+06
    q /= 10;
    ++e;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%llu.%04llue+%02d", q / 10000, q % 10000, e);
  return buf;
}

template <class T>
T at(const std::vector<T>& v, std::size_t i, T fallback) {
  return i < v.size() ? v[i] : fallback;
}

// One row, with Stable32's widths for the statistic's kind of table.
std::string row(kernels::Stable32Row layout, const kernels::StatResult& s, std::size_t i,
                std::int64_t count) {
  char buf[200];
  const auto m = static_cast<long long>(s.m[i]);
  const auto n = static_cast<long long>(count);
  if (layout == kernels::Stable32Row::TimeError) {
    std::snprintf(buf, sizeof buf, "%5lld   %s%9lld   %s\n", m, e4(s.tau_s[i]).c_str(), n,
                  e4(s.dev[i]).c_str());
    return buf;
  }
  const bool ci = s.confidence > 0.0;
  const std::string lo = e4(ci ? at(s.dev_lo, i, 0.0) : 0.0);
  const std::string hi = e4(ci ? at(s.dev_hi, i, 0.0) : 0.0);
  const int alpha = at(s.alpha, i, 0);
  if (layout == kernels::Stable32Row::Theo) {
    // Thêo1's "#" is a weighted count, printed as a number (phase_dat_theo1.txt).
    std::snprintf(buf, sizeof buf, "%4lld  %s  %s%7d  %s %s %s\n", m, e4(s.tau_s[i]).c_str(),
                  e4_count(n).c_str(), alpha, lo.c_str(), e4(s.dev[i]).c_str(), hi.c_str());
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%5lld   %s%9lld%6d   %s    %s     %s\n", m,
                e4(s.tau_s[i]).c_str(), n, alpha, lo.c_str(), e4(s.dev[i]).c_str(), hi.c_str());
  return buf;
}

}  // namespace

std::string stable32_table(const Stable32Head& head, const std::string& stat,
                           const kernels::StatResult& s) {
  const kernels::StatInfo& l = info_of(stat);
  std::ostringstream o;
  char buf[160];
  o << "# STATISTICS FOR FILE: " << head.file << "\n";
  std::snprintf(buf, sizeof buf, "# %s Data Points 1 thru %lld of %lld\n",
                head.phase ? "Phase" : "Frequency", static_cast<long long>(head.n_points),
                static_cast<long long>(head.n_points));
  o << buf;
  if (std::isfinite(head.mean)) {
    std::snprintf(buf, sizeof buf, "# Maximum = %.6e\n# Minimum = %.6e\n# Average = %.6e\n",
                  head.max, head.min, head.mean);
    o << buf;
  }
  const bool mtie = l.id == kernels::Stat::Mtie;
  o << "# Sigma Type: " << l.stable32_sigma_type << (mtie && head.mtie_fast ? " (Fast)" : "")
    << "\n";
  if (l.stable32_row != kernels::Stable32Row::TimeError) {
    std::snprintf(buf, sizeof buf, "# Confidence Factor = %.3f\n", s.confidence);
    o << buf;
  }
  o << "# Deadtime T/Tau = 1.000000\n#\n" << l.stable32_title << "\n";
  for (std::size_t i = 0; i < s.size(); ++i) {
    // Stable32's non-fast MTIE prints the N points analysed as "#" and stops at its stop ratio
    // 2, m <= (N - 1) / 2; its fast MTIE prints the N - m windows up to m = N - 1.
    const bool slow_mtie = mtie && !head.mtie_fast;
    if (slow_mtie && s.m[i] > (head.n_points - 1) / 2) continue;
    o << row(l.stable32_row, s, i, slow_mtie ? head.n_points : s.n[i]);
  }
  o << head.trailer;
  return o.str();
}

}  // namespace allanlot::io
