// What the command line says about input recordings that the files themselves may not
// (docs/cli.md "Input options"): shared by every command that reads recordings.
#pragma once

#include "kernels/allan/phase.hpp"

#include <optional>
#include <string>

namespace allanlot::io {

struct InputOptions {
  /// --data-type: the data type of every channel, overriding the files' `data_type`.
  std::optional<kernels::DataType> data_type;
  /// --sample-rate HZ or 1 / --tau0 S; 0 when not given. Text recordings without a time
  /// column need it; a text recording with one takes it instead of the time steps.
  double sample_rate_hz = 0.0;
  /// --column N: the 1-based column of a headerless text recording that holds the values.
  int column = 0;
  std::string time_column;  // --time-column NAME: the time column of a CSV/TSV
  std::string time_unit;    // --time-unit s|ms|us|ns: the unit of a numeric time column
  std::string units;        // --units: the unit of the text columns that name none
};

}  // namespace allanlot::io
