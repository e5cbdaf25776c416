#include "kernels/powerlaw/names.hpp"

#include "kernels/model/units.hpp"

#include <stdexcept>
#include <string>

namespace allanlot::kernels::powerlaw {

bool is_clock_channel(std::string_view units, std::string_view data_type) {
  const kernels::units::Family f = kernels::units::family_of(units);
  if (f == kernels::units::Family::Clock) return true;
  return data_type.starts_with("phase") && f == kernels::units::Family::Other;
}

std::size_t level_index(int alpha) {
  if (alpha < -2 || alpha > 2)
    throw std::invalid_argument("power-law alpha must be in -2..2, got " + std::to_string(alpha));
  return static_cast<std::size_t>(2 - alpha);
}

std::string_view noise_type_name(int alpha) {
  switch (alpha) {
  case 2:
    return "white PM";
  case 1:
    return "flicker PM";
  case 0:
    return "white FM";
  case -1:
    return "flicker FM";
  case -2:
    return "random-walk FM";
  default:
    return "";
  }
}

std::string_view noise_type_name_long(int alpha) {
  if (alpha == -3) return "flicker walk FM";
  if (alpha == -4) return "random run FM";
  return noise_type_name(alpha);
}

}  // namespace allanlot::kernels::powerlaw
