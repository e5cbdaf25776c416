// libFuzzer target: manifest expansion and the --channels matcher and selection
// (src/workflow/inputs.cpp). The input is written as a manifest file, whose lines name paths
// relative to it (some exist: the manifest itself, its directory); expansion must never throw, list
// a path twice, list more paths than the manifest has lines that are neither blank nor comments, or
// pass over an empty manifest in silence. The same bytes, split in two, are a glob and a channel
// path.
#include "src/workflow/inputs.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace {

const std::filesystem::path& workdir() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    auto d = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
             ("allanlot-fuzz-manifest." + std::to_string(::getpid()));
    std::filesystem::create_directories(d / "sub");
    std::ofstream(d / "sub" / "a.h5") << "x";
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto manifest = workdir() / "m.txt";
  std::ofstream(manifest, std::ios::binary | std::ios::trunc) << text;
  const workflow::InputList list = workflow::expand_inputs({"@" + manifest.string()});
  // The lines that name a recording: not blank, not a comment after trimming.
  std::size_t listed = 0;
  for (std::size_t b = 0; b <= text.size();) {
    const std::size_t e = std::min(text.find('\n', b), text.size());
    const std::string line = text.substr(b, e - b);
    const auto first = line.find_first_not_of(" \t\r\n");
    listed += first != std::string::npos && line[first] != '#' ? 1 : 0;
    b = e + 1;
  }
  std::set<std::string> seen;
  for (const std::string& f : list.files)
    if (f.empty() || !seen.insert(f).second) std::abort();
  if (list.files.size() > listed) std::abort();
  if (listed == 0 && list.failures.empty()) std::abort();  // an empty manifest is named
  const auto cut = text.find('\n');
  const std::string glob = text.substr(0, cut);
  const std::string path = cut == std::string::npos ? std::string() : text.substr(cut + 1);
  (void)workflow::channel_matches(glob, path);
  // The same line as a --channels list: what it selects is what its own text selects again
  // (the resume stamp stands for the selection).
  try {
    const workflow::ChannelSelection sel({glob}, {});
    const workflow::ChannelSelection again({sel.text()}, {});
    if (sel.selects(path) != again.selects(path) || again.text() != sel.text()) std::abort();
  } catch (const std::invalid_argument&) {
    // A '!' without a glob: a usage error.
  }
  return 0;
}
