#include "src/cli/inputs.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

namespace fs = std::filesystem;

namespace allanlot::cli {
namespace {

bool is_recording_name(const fs::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".h5" || ext == ".hdf5";
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

void add_file(InputList& out, std::set<std::string>& seen, const std::string& path) {
  std::error_code ec;
  const fs::path canon = fs::weakly_canonical(path, ec);
  const std::string key = ec ? path : canon.string();
  if (seen.insert(key).second) out.files.push_back(path);
}

void add_directory(InputList& out, std::set<std::string>& seen, const std::string& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  if (ec) {
    out.failures.emplace_back(dir, "cannot read directory: " + ec.message());
    return;
  }
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) {
      out.failures.emplace_back(dir, "error while listing: " + ec.message());
      break;
    }
    const fs::path& p = it->path();
    if (p.filename().string().starts_with(".")) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file(ec) && is_recording_name(p)) found.push_back(p.string());
  }
  std::sort(found.begin(), found.end());
  if (found.empty()) out.failures.emplace_back(dir, "directory contains no *.h5 or *.hdf5 file");
  for (const auto& f : found)
    add_file(out, seen, f);
}

}  // namespace

InputList expand_inputs(const std::vector<std::string>& inputs) {
  InputList out;
  std::set<std::string> seen;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      add_directory(out, seen, in);
    } else if (fs::path(in).extension() == ".txt") {
      std::ifstream manifest(in);
      if (!manifest) {
        out.failures.emplace_back(in, "cannot open manifest");
        continue;
      }
      const fs::path base = fs::path(in).parent_path();
      std::string line;
      std::size_t listed = 0;
      while (std::getline(manifest, line)) {
        line = trim(line);
        if (line.empty() || line[0] == '#') continue;
        const fs::path p(line);
        add_file(out, seen, (p.is_absolute() || base.empty() ? p : base / p).string());
        ++listed;
      }
      // An empty manifest (a batch system's list that came out empty) is a failed input, not
      // a silent "analysed 0 of 0".
      if (listed == 0) out.failures.emplace_back(in, "manifest lists no recording");
    } else {
      add_file(out, seen, in);
    }
  }
  return out;
}

bool channel_matches(const std::string& glob, const std::string& path) {
  if (glob.empty()) return true;
  const std::string name = path.substr(path.find_last_of('/') + 1);
  return fnmatch(glob.c_str(), path.c_str(), 0) == 0 || fnmatch(glob.c_str(), name.c_str(), 0) == 0;
}

}  // namespace allanlot::cli
