#include "src/cli/input_options.hpp"

#include "io/error.hpp"
#include "io/recording.hpp"
#include "io/usage_error.hpp"
#include "kernels/model/units.hpp"
#include "src/cli/cli.hpp"
#include "src/cli/memory.hpp"

#include <sstream>

namespace allanlot::cli {

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
        throw CLI::ValidationError("--units", what + ": give UNIT or GLOB=UNIT");
      if (!kernels::units::parse_channel_units(r.unit))
        throw CLI::ValidationError(
            "--units", what + ": '" + r.unit + "' is not a unit allanlot knows" +
                           (r.glob.empty() ? "" : " (for the columns '" + r.glob + "')") +
                           " (docs/formats.md#units-and-conventions)");
      rules.push_back(r);
    }
  }
  return rules;
}

}  // namespace

void add_input_options(CLI::App* sub, InputArgs& a) {
  sub->add_option("--data-type", a.data_type,
                  "rate or phase, for every channel (overrides the files; text files with one "
                  "column need it)")
      ->check(CLI::IsMember({"rate", "phase"}));
  auto* rate = sub->add_option("--sample-rate", a.sample_rate_hz,
                               "Sample rate in Hz of text files without a time column")
                   ->check(finite_number() & CLI::PositiveNumber);
  sub->add_option("--tau0", a.tau0_s, "Sample interval in s (instead of --sample-rate)")
      ->check(finite_number() & CLI::PositiveNumber)
      ->excludes(rate);
  sub->add_option("--column", a.options.column,
                  "The value column (1-based) of a text file without a header")
      ->check(CLI::Range(1, 1 << 20));
  sub->add_option("--time-column", a.options.time_column,
                  "The time column of a CSV/TSV file, by its header name");
  sub->add_option("--time-unit", a.time_unit, "Unit of a numeric time column: s, ms, us or ns")
      ->check(CLI::IsMember({"s", "ms", "us", "ns"}));
  sub->add_option("--units", a.units,
                  "Units of text columns: UNIT for those whose header names none, GLOB=UNIT for "
                  "the columns the glob matches (comma-separated, repeatable)")
      ->allow_extra_args(false);
  sub->add_option("--topic", a.options.topics,
                  "sensor_msgs/Imu topics of a ROS bag or MCAP file to read (globs, repeatable; "
                  "default every Imu topic)")
      ->allow_extra_args(false);
  sub->add_flag("--receive-time", a.options.receive_time,
                "Time a bag's messages by when they were recorded, not by their header stamps");
  sub->add_option("--nominal-frequency", a.nominal_frequency_hz,
                  "Nominal frequency F in Hz of clock channels in Hz, read as fractional "
                  "frequency (f - F) / F")
      ->check(finite_number() & CLI::PositiveNumber);
}

io::InputOptions input_options(const InputArgs& a) {
  io::InputOptions o = a.options;
  if (a.data_type == "rate") o.data_type = kernels::DataType::Rate;
  if (a.data_type == "phase") o.data_type = kernels::DataType::Phase;
  o.sample_rate_hz = a.tau0_s > 0 ? 1.0 / a.tau0_s : a.sample_rate_hz;
  if (a.tau0_s > 0 &&
      !(o.sample_rate_hz >= io::kMinSampleRateHz && o.sample_rate_hz <= io::kMaxSampleRateHz))
    throw CLI::ValidationError("--tau0", "outside 1e-12 .. 1e9 s");
  if (a.sample_rate_hz > 0 &&
      !(a.sample_rate_hz >= io::kMinSampleRateHz && a.sample_rate_hz <= io::kMaxSampleRateHz))
    throw CLI::ValidationError("--sample-rate", "outside 1e-9 .. 1e12 Hz");
  o.time_unit = a.time_unit;
  o.units = column_units(a.units);
  o.nominal_frequency_hz = a.nominal_frequency_hz;
  for (const io::ColumnUnits& r : o.units)
    if (const auto known = kernels::units::parse_channel_units(r.unit);
        known && known->per_nominal && o.nominal_frequency_hz <= 0)
      throw CLI::ValidationError(
          "--units", "'" + r.unit + "'" +
                         (r.glob.empty() ? "" : " for the columns '" + r.glob + "'") +
                         " is a frequency: give --nominal-frequency F (Hz) to read it as "
                         "fractional frequency (f - F) / F");
  // Commands without --memory-limit bound a text recording as analyze does by default.
  o.memory_limit = physical_memory() / 2;
  return o;
}

void add_channel_options(CLI::App* sub, std::vector<std::string>& include,
                         std::vector<std::string>& exclude) {
  sub->add_option("--channels", include,
                  "Only channels whose path or name matches one of these globs (comma-separated, "
                  "repeatable; !GLOB excludes)")
      ->allow_extra_args(false);
  sub->add_option("--exclude-channels", exclude,
                  "Leave out channels whose path or name matches one of these globs "
                  "(comma-separated, repeatable)")
      ->allow_extra_args(false);
}

ChannelSelection channel_selection(const std::vector<std::string>& include,
                                   const std::vector<std::string>& exclude) {
  try {
    return ChannelSelection(include, exclude);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--channels", e.what());
  }
}

void check_inputs_need(const std::vector<std::string>& files, const io::InputOptions& options) {
  for (const std::string& f : files) {
    try {
      io::check_input_options(f, options);
    } catch (const io::UsageError& e) {
      throw CLI::ValidationError(e.what());
    } catch (const io::Error&) {
      // Any other problem of the file is its own failure, reported when it is read.
    }
  }
}

}  // namespace allanlot::cli
