#include "src/workflow/notes.hpp"

#include <ostream>
#include <streambuf>

namespace allanlot::workflow {
namespace {

// A stream buffer that takes every character and keeps none.
class Discard : public std::streambuf {
protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

}  // namespace

std::ostream& notes_stream(bool quiet, std::ostream& err) {
  if (!quiet) return err;
  // One per thread: a stream's state (its width, reset by every <<) is not shared.
  thread_local Discard buffer;
  thread_local std::ostream discard(&buffer);
  return discard;
}

}  // namespace allanlot::workflow
