#include "src/workflow/input_args.hpp"

#include "io/recording.hpp"
#include "kernels/model/units.hpp"

#include <unistd.h>

#include <sstream>

namespace allanlot::workflow {
namespace {

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// --units [GLOB=]UNIT,...: each unit one of the vocabulary (kernels/model/units.hpp), so that
// a misspelt unit is a usage error before any work, not coefficients without datasheet units.
std::vector<io::ColumnUnits> column_units(const std::vector<std::string>& given) {
  std::vector<io::ColumnUnits> rules;
  for (const std::string& list : given) {
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
      const auto eq = item.find('=');
      io::ColumnUnits r;
      if (eq != std::string::npos) r.glob = trimmed(item.substr(0, eq));
      r.unit = trimmed(eq == std::string::npos ? item : item.substr(eq + 1));
      const std::string what = "'" + item + "'";
      if (r.unit.empty() || (eq != std::string::npos && r.glob.empty()))
        throw OptionError("--units", what + ": give UNIT or GLOB=UNIT");
      if (!kernels::units::parse_channel_units(r.unit))
        throw OptionError("--units",
                          what + ": '" + r.unit + "' is not a unit allanlot knows" +
                              (r.glob.empty() ? "" : " (for the columns '" + r.glob + "')") +
                              " (docs/formats.md#units-and-conventions)");
      rules.push_back(r);
    }
  }
  return rules;
}

}  // namespace

io::InputOptions checked_input_options(const InputArgs& a) {
  io::InputOptions o = a.options;
  if (a.data_type == "rate") o.data_type = kernels::DataType::Rate;
  if (a.data_type == "phase") o.data_type = kernels::DataType::Phase;
  o.sample_rate_hz = a.tau0_s > 0 ? 1.0 / a.tau0_s : a.sample_rate_hz;
  if (a.tau0_s > 0 &&
      !(o.sample_rate_hz >= io::kMinSampleRateHz && o.sample_rate_hz <= io::kMaxSampleRateHz))
    throw OptionError("--tau0", "outside 1e-12 .. 1e9 s");
  if (a.sample_rate_hz > 0 &&
      !(a.sample_rate_hz >= io::kMinSampleRateHz && a.sample_rate_hz <= io::kMaxSampleRateHz))
    throw OptionError("--sample-rate", "outside 1e-9 .. 1e12 Hz");
  o.time_unit = a.time_unit;
  o.units = column_units(a.units);
  o.nominal_frequency_hz = a.nominal_frequency_hz;
  for (const io::ColumnUnits& r : o.units)
    if (const auto known = kernels::units::parse_channel_units(r.unit);
        known && known->per_nominal && o.nominal_frequency_hz <= 0)
      throw OptionError("--units",
                        "'" + r.unit + "'" +
                            (r.glob.empty() ? "" : " for the columns '" + r.glob + "'") +
                            " is a frequency: give --nominal-frequency F (Hz) to read it as "
                            "fractional frequency (f - F) / F");
  // Commands without --memory-limit bound a text recording as analyze does by default.
  o.memory_limit = physical_memory() / 2;
  return o;
}

std::uint64_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0
             ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page)
             : std::uint64_t{8} << 30;
}

}  // namespace allanlot::workflow
