#include "io/growing.hpp"

#include "io/error.hpp"
#include "io/recording.hpp"

#include <fstream>
#include <iterator>
#include <string>

namespace allanlot::io {

std::string growing_snapshot(const std::string& path, const std::filesystem::path& dir,
                             std::uintmax_t* bytes_seen) {
  if (!is_text_recording(path)) return path;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot open the recording");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto last = text.rfind('\n');
  text.resize(last == std::string::npos ? 0 : last + 1);
  if (text.size() <= *bytes_seen) return "";
  *bytes_seen = text.size();
  const std::filesystem::path copy = dir / std::filesystem::path(path).filename();
  std::ofstream out(copy, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out.flush()) throw Error(path, "", "cannot write its snapshot " + copy.string());
  return copy.string();
}

}  // namespace allanlot::io
