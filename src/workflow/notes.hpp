// Where notes and warnings go under -q/--quiet (docs/cli.md "Exit statuses and messages"):
// errors are always said, notes only when asked for.
#pragma once

#include <iosfwd>

namespace allanlot::workflow {

/// The stream for notes and warnings: `err`, or one that discards them under -q/--quiet, which
/// prints errors only. Errors are always written to `err` itself.
std::ostream& notes_stream(bool quiet, std::ostream& err);

}  // namespace allanlot::workflow
