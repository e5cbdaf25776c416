#include "src/cli/input_options.hpp"

#include "io/error.hpp"
#include "io/recording.hpp"
#include "io/usage_error.hpp"
#include "src/cli/cli.hpp"

namespace allanlot::cli {

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
  sub->add_option("--units", a.options.units, "Units of the text columns whose header names none");
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
  return o;
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
