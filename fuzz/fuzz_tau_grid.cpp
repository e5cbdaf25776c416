// libFuzzer target: the --taus and --stats parsers (kernels/allan/tau_grid.hpp,
// kernels/allan/stats.hpp). Text must parse or throw std::invalid_argument; a parsed grid must give
// averaging factors that are strictly increasing and within [1, m_max] for any m_max, and print
// back to a text that parses to the same factors.
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"

#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot::kernels;
  FuzzedDataProvider in(data, size);
  // m_max as small as no tau and as large as a week at 1 kHz over 2 (totdev's limit), so that
  // the dense grids stay cheap: the grids' cost is linear in m_max only for "all".
  const auto m_max = in.ConsumeIntegralInRange<std::int64_t>(-3, 1 << 20);
  const auto n_points = in.ConsumeIntegralInRange<std::int64_t>(-3, std::int64_t{1} << 40);
  const std::string text = in.ConsumeRemainingBytesAsString();
  (void)parse_stat(text);
  TauGridSpec spec;
  try {
    spec = parse_tau_grid(text);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  if (spec.kind == TauGridKind::All && m_max > (1 << 16)) return 0;
  const auto ms = make_m_list(spec, m_max, n_points);
  for (std::size_t i = 0; i < ms.size(); ++i)
    if (ms[i] < 1 || ms[i] > m_max || (i > 0 && ms[i] <= ms[i - 1])) std::abort();
  if (make_m_list(parse_tau_grid(to_string(spec)), m_max, n_points) != ms) std::abort();
  return 0;
}
