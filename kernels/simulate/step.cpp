// The step effect's samples and process hooks (step.hpp; its Allan variance over a record is
// steps_avar.cpp).
#include "kernels/simulate/step.hpp"

#include <algorithm>

namespace allanlot::kernels {

void add_steps(std::span<double> y, std::span<const Step> steps, double rate_hz, double scale,
               std::size_t first) {
  for (const Step& st : steps) {
    const double s_at = st.time_s * rate_hz, d = scale * st.size;
    for (std::size_t i = 0; i < y.size(); ++i)
      y[i] += d * std::clamp(static_cast<double>(first + i) + 1.0 - s_at, 0.0, 1.0);
  }
}

void add_effect_block(const Step& st, double rate_hz, std::size_t first, std::span<double> y) {
  add_steps(y, std::span(&st, 1), rate_hz, 1.0, first);
}

double effect_avar(const Step&, double, double) {
  return 0.0;
}

double plus_record_avar(double avar, std::span<const Step> steps, double rate_hz, std::int64_t m,
                        std::int64_t n_samples) {
  return plus_steps_avar(avar, steps, rate_hz, m, n_samples);
}

double filter_change_avar(const Step&, const FilterAt&) {
  return 0.0;
}

void add_effect_psd(const Step&, double, std::span<const double>, std::vector<double>&) {}

}  // namespace allanlot::kernels
