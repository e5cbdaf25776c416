// libFuzzer target: the model file parser (src/lot/model.cpp). Any text must either parse into a
// model that validates and survives a round trip through to_json, or be rejected with a
// model::Error; nothing else may escape, crash or trip a sanitizer.
#include "src/lot/model.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  model::UnitModel m;
  try {
    m = model::parse_model(text, "fuzz.json");
  } catch (const model::Error&) {
    return 0;
  }
  // A model that parsed is valid and writes back to itself (model.hpp's round-trip promise).
  model::validate(m, "fuzz.json");
  if (!(model::parse_model(model::to_json(m), "round-trip.json") == m)) std::abort();
  return 0;
}
