// The I/O error type: every message names the file, the dataset (when there is one) and the
// reason, e.g. "read /data/run7.h5:/sensors/gyro_x: H5Dread failed".
#pragma once

#include <stdexcept>
#include <string>

namespace allanlot::io {

class Error : public std::runtime_error {
public:
  Error(std::string file, std::string dataset, std::string reason);
  const std::string& file() const { return file_; }
  const std::string& dataset() const { return dataset_; }
  const std::string& reason() const { return reason_; }

private:
  std::string file_, dataset_, reason_;
};

}  // namespace allanlot::io
