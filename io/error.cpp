#include "io/error.hpp"

namespace allanlot::io {
namespace {
std::string compose(const std::string& file, const std::string& dataset,
                    const std::string& reason) {
  std::string where = file;
  if (!dataset.empty()) where += ":" + dataset;
  return where + ": " + reason;
}
}  // namespace

Error::Error(std::string file, std::string dataset, std::string reason)
    : std::runtime_error(compose(file, dataset, reason)), file_(std::move(file)),
      dataset_(std::move(dataset)), reason_(std::move(reason)) {}

}  // namespace allanlot::io
