#include "src/workflow/inputs.hpp"

#include "io/paths.hpp"
#include "io/recording_source.hpp"
#include "io/text_fields.hpp"
#include "io/usage_error.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace fs = std::filesystem;

namespace allanlot::workflow {
namespace {

// What a directory search takes for a recording, by the end of its name in any case
// (`UNIT.H5` as well). Not .txt or .dat, which a data folder also holds as notes, READMEs and
// manifests: those are recordings only when given by name.
constexpr const char* kDirectoryExtensions[] = {".h5",     ".hdf5", ".csv",  ".tsv", ".csv.gz",
                                                ".tsv.gz", ".bag",  ".mcap", ".db3"};

// Results files and lot summaries are outputs, never recordings: a directory holding earlier
// results (an OUTDIR inside the input tree) must not have them analysed as units.
bool is_recording_name(const fs::path& p) {
  const std::string name = io::ascii_lower(p.filename().string());
  if (name.ends_with(".allan.h5") || name == "lot_summary.h5" || name == "lot_summary.csv")
    return false;
  return std::any_of(
      std::begin(kDirectoryExtensions), std::end(kDirectoryExtensions),
      [&](std::string_view ext) { return name.size() > ext.size() && name.ends_with(ext); });
}

std::string no_recording_reason() {
  std::string s = "directory contains no recording (looked for";
  for (const char* ext : kDirectoryExtensions)
    s += std::string(ext == kDirectoryExtensions[0] ? " *" : ", *") + ext;
  return s + "; give other files by name)";
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

struct Expansion {
  InputList out;
  std::set<std::string> seen;
  fs::path exclude;  // OUTDIR: never searched
};

// A folder that is one recording (a ROS 2 bag: metadata.yaml beside its storage files).
bool is_recording_folder(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && io::find_source_format(path) != nullptr;
}

void add_file(Expansion& x, const std::string& path) {
  // open(2) of a FIFO blocks until a writer comes: refuse anything but a regular file before
  // any reader opens it.
  if (const std::string problem = io::input_file_problem(path);
      !problem.empty() && !is_recording_folder(path)) {
    x.out.failures.emplace_back(path, problem);
    return;
  }
  std::error_code ec;
  const fs::path canon = fs::weakly_canonical(path, ec);
  const std::string key = ec ? path : canon.string();
  if (x.seen.insert(key).second) x.out.files.push_back(path);
}

// A directory to descend into: not hidden, not OUTDIR, and not one already visited (a link
// back up the tree would otherwise be followed for ever).
bool enter_directory(const fs::directory_entry& e, Expansion& x,
                     std::set<std::pair<dev_t, ino_t>>& visited) {
  struct stat st {};
  if (::stat(e.path().c_str(), &st) != 0) return false;
  if (!x.exclude.empty() && io::same_file(e.path(), x.exclude)) return false;
  return visited.insert({st.st_dev, st.st_ino}).second;
}

void add_directory(Expansion& x, const std::string& dir) {
  std::vector<std::string> found;
  std::set<std::pair<dev_t, ino_t>> visited;
  std::error_code ec;
  if (!x.exclude.empty() && io::same_file(dir, x.exclude)) {
    x.out.failures.emplace_back(dir, "is the output directory; its results are never inputs");
    return;
  }
  enter_directory(fs::directory_entry(dir, ec), x, visited);
  const auto options = fs::directory_options::skip_permission_denied |
                       fs::directory_options::follow_directory_symlink;
  fs::recursive_directory_iterator it(dir, options, ec);
  if (ec) {
    x.out.failures.emplace_back(dir, "cannot read directory: " + ec.message());
    return;
  }
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) {
      x.out.failures.emplace_back(dir, "error while listing: " + ec.message());
      break;
    }
    const fs::path& p = it->path();
    const bool hidden = p.filename().string().starts_with(".");
    if (it->is_directory(ec)) {
      if (!hidden && is_recording_folder(p.string())) found.push_back(p.string());
      if (hidden || is_recording_folder(p.string()) || !enter_directory(*it, x, visited))
        it.disable_recursion_pending();
      continue;
    }
    if (!hidden && is_recording_name(p)) found.push_back(p.string());
  }
  std::sort(found.begin(), found.end());
  if (found.empty()) x.out.failures.emplace_back(dir, no_recording_reason());
  for (const auto& f : found)
    add_file(x, f);
}

void add_manifest(Expansion& x, const std::string& in) {
  std::ifstream manifest(in);
  if (!manifest) {
    x.out.failures.emplace_back(in, "cannot open manifest");
    return;
  }
  const fs::path base = fs::path(in).parent_path();
  std::string line;
  std::size_t listed = 0;
  for (bool first = true; std::getline(manifest, line); first = false) {
    if (first && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);  // a UTF-8 byte-order mark
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const fs::path p(line);
    add_file(x, (p.is_absolute() || base.empty() ? p : base / p).string());
    ++listed;
  }
  // An empty manifest (a batch system's list that came out empty) is a failed input, not
  // a silent "analysed 0 of 0".
  if (listed == 0) x.out.failures.emplace_back(in, "manifest lists no recording");
}

// A .txt file given as an input is data; one whose lines are all existing paths was meant as
// a manifest, and analysing it as numbers would only fail line by line.
bool looks_like_manifest(const std::string& in) {
  if (io::ascii_lower(fs::path(in).extension().string()) != ".txt") return false;
  std::ifstream f(in);
  const fs::path base = fs::path(in).parent_path();
  std::string line;
  std::size_t paths = 0;
  while (std::getline(f, line) && paths < 10000) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const fs::path p(line);
    std::error_code ec;
    if (!fs::exists(p.is_absolute() || base.empty() ? p : base / p, ec)) return false;
    ++paths;
  }
  return paths > 0;
}

}  // namespace

InputList expand_inputs(const std::vector<std::string>& inputs, const fs::path& outdir) {
  Expansion x;
  x.exclude = outdir;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (in.starts_with("@"))
      add_manifest(x, in.substr(1));
    else if (fs::is_directory(in, ec) && !is_recording_folder(in))
      add_directory(x, in);
    else if (looks_like_manifest(in))
      throw OptionError(in, "every line names an existing file: to read it as a manifest, give "
                            "it as @" +
                                in + " (or --manifest " + in + ")");
    else
      add_file(x, in);
  }
  return std::move(x.out);
}

bool channel_matches(const std::string& glob, const std::string& path) {
  return io::channel_glob_matches(glob, path);
}

ChannelSelection::ChannelSelection(const std::vector<std::string>& include,
                                   const std::vector<std::string>& exclude) {
  // Each list split at commas; `!GLOB` among the includes is an exclude.
  const auto add = [this](const std::string& list, bool excluding) {
    std::stringstream ss(list);
    std::string glob;
    while (std::getline(ss, glob, ',')) {
      glob = trim(glob);
      const bool negated = !excluding && glob.starts_with("!");
      if (negated) {
        glob = trim(glob.substr(1));
        if (glob.empty()) throw std::invalid_argument("'!' names no glob in '" + list + "'");
      }
      if (glob.empty()) continue;
      (excluding || negated ? exclude_ : include_).push_back(glob);
    }
  };
  for (const std::string& list : include)
    add(list, false);
  for (const std::string& list : exclude)
    add(list, true);
}

bool ChannelSelection::selects(const std::string& path) const {
  const auto match = [&](const std::string& glob) { return channel_matches(glob, path); };
  return (include_.empty() || std::any_of(include_.begin(), include_.end(), match)) &&
         std::none_of(exclude_.begin(), exclude_.end(), match);
}

std::vector<std::string> ChannelSelection::unmatched(const std::vector<std::string>& paths) const {
  std::vector<std::string> out;
  for (const std::string& glob : include_)
    if (std::none_of(paths.begin(), paths.end(),
                     [&](const std::string& p) { return channel_matches(glob, p); }))
      out.push_back(glob);
  return out;
}

std::string ChannelSelection::text() const {
  std::string s;
  for (const std::string& g : include_)
    s += (s.empty() ? "" : ",") + g;
  for (const std::string& g : exclude_)
    s += (s.empty() ? "!" : ",!") + g;
  return s;
}

namespace {

std::vector<std::string> channel_paths(const io::RecordingInfo& info) {
  std::vector<std::string> paths;
  for (const io::ChannelInfo& ch : info.channels)
    paths.push_back(ch.path);
  for (const io::ChannelProblem& p : info.problems)
    paths.push_back(p.path);
  return paths;
}

}  // namespace

std::string unselected_reason(const ChannelSelection& selection, const io::RecordingInfo& info) {
  std::string list;
  for (const std::string& p : channel_paths(info))
    list += (list.empty() ? "" : ", ") + p;
  // The selection as one --channels list: the excludes of --exclude-channels as '!' globs.
  return "no channel matches --channels '" + selection.text() + "' (its channels: " + list + ")";
}

void note_unmatched(const std::string& file, const ChannelSelection& selection,
                    const io::RecordingInfo& info, std::ostream& notes) {
  for (const std::string& glob : selection.unmatched(channel_paths(info)))
    notes << "allanlot: note: " << file << ": --channels '" << glob
          << "' matches no channel of this recording\n";
}

void check_inputs_need(const std::vector<std::string>& files, const io::InputOptions& options) {
  for (const std::string& f : files) {
    try {
      io::check_input_options(f, options);
    } catch (const io::UsageError&) {
      throw;
    } catch (const io::Error&) {
      // Any other problem of the file is its own failure, reported when it is read.
    }
  }
}

}  // namespace allanlot::workflow
