#include "src/workflow/status.hpp"

#include "src/lot/spec.hpp"

#include <string>

namespace allanlot::workflow {

int print_usage_error(const std::exception_ptr& e, std::ostream& err) {
  try {
    std::rethrow_exception(e);
  } catch (const spec::Error& x) {
    // A spec reports every mistake it found at once, one line each.
    for (const std::string& msg : x.messages())
      err << "allanlot: error: " << msg << "\n";
  } catch (const std::exception& x) {
    err << "allanlot: error: " << x.what() << "\n";
  }
  return kExitUsage;
}

}  // namespace allanlot::workflow
