// The I/O error that is the command line's fault: an input needs what only an option can say.
#pragma once

#include "io/error.hpp"

namespace allanlot::io {

/// An input that needs what only the command line can say (a text recording's data type or
/// sample rate): a usage error, exit status 2, never a guess.
class UsageError : public Error {
public:
  using Error::Error;
};

}  // namespace allanlot::io
