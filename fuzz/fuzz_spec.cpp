// libFuzzer target: the spec file parser (src/lot/spec.cpp). Any text must parse or be rejected
// with a spec::Error; a parsed spec must give a verdict on a summary row without escaping
// anything but spec::Error (a rule whose unit does not fit the channel).
#include "src/lot/spec.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  spec::Spec s;
  try {
    s = spec::parse_spec(text, "fuzz.json");
  } catch (const spec::Error&) {
    return 0;
  }
  if (!(s.confidence > 0 && s.confidence < 1) || !std::isfinite(s.k) || s.rules.empty())
    std::abort();
  for (const char* units : {"deg/s", "m/s^2", "s"}) {
    io::SummaryRow row("unit", "/imu/gyro_x", units, 1000, io::ChannelStatus::ok(), "u.h5");
    // Datasheet values as the summary holds them, each in its term's primary datasheet unit.
    for (std::size_t t = 0; t < row.value.size(); ++t) {
      row.unit[t] =
          kernels::units::to_datasheet(kernels::units::all_terms()[t], 1.0, units).primary.unit;
      row.value[t] = 1.0;
      row.sigma[t] = 0.1;
      row.upper[t] = 1.2;
      row.detected[t] = t % 2;
    }
    try {
      (void)spec::judge(s, row);
    } catch (const spec::Error&) {
    }
  }
  return 0;
}
