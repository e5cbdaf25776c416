#include "io/paths.hpp"

#include "io/atomic_file.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <regex>
#include <sys/stat.h>

namespace fs = std::filesystem;

namespace allanlot::io {

bool same_file(const fs::path& a, const fs::path& b) {
  struct stat sa {};
  struct stat sb {};
  if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) return false;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

std::optional<fs::path> replaced_input(const fs::path& output, std::span<const fs::path> inputs) {
  for (const fs::path& in : inputs)
    if (same_file(output, in)) return in;
  return std::nullopt;
}

std::string outputs_conflict(std::span<const fs::path> outputs, std::span<const fs::path> inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].empty()) continue;
    if (const auto in = replaced_input(outputs[i], inputs))
      return replaced_input_message(outputs[i], *in);
    for (std::size_t j = i + 1; j < outputs.size(); ++j)
      if (!outputs[j].empty() && (outputs[i] == outputs[j] || same_file(outputs[i], outputs[j])))
        return "outputs " + outputs[i].string() + " and " + outputs[j].string() +
               " are the same file";
  }
  return "";
}

std::string replaced_input_message(const fs::path& output, const fs::path& input) {
  return "output " + output.string() + " is the input " + input.string() +
         (output == input ? "" : " (the same file)") + "; it would be overwritten";
}

bool is_within(const fs::path& path, const fs::path& dir) {
  std::error_code ec1, ec2;
  const fs::path p = fs::canonical(path, ec1);
  const fs::path d = fs::canonical(dir, ec2);
  if (ec1 || ec2) return false;
  auto pi = p.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++pi)
    if (pi == p.end() || *pi != *di) return false;
  return true;
}

std::string input_file_problem(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return errno == ENOENT ? "no such file" : std::strerror(errno);
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "is a directory";
  if (S_ISFIFO(st.st_mode)) return "not a regular file (a FIFO)";
  if (S_ISSOCK(st.st_mode)) return "not a regular file (a socket)";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "not a regular file (a device)";
  return "not a regular file";
}

std::size_t remove_stale_temporaries(const fs::path& dir, fs::file_time_type before) {
  // io::AtomicFile's names: '.', the final name (cut to fit), ".tmp.", host, '.', pid, '.', n.
  static const std::regex pattern(R"(^\..+\.tmp\.([A-Za-z0-9_-]*)\.([0-9]+)\.[0-9]+$)");
  const std::string this_host = host_tag();
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, pattern) || !e.is_regular_file(ec)) continue;
    if (e.last_write_time(ec) >= before || ec) continue;
    // A writer on this host that is still alive (another run) keeps its file.
    const long pid = std::stol(m[2].str());
    if (m[1].str() == this_host && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM))
      continue;
    if (fs::remove(e.path(), ec)) ++removed;
  }
  return removed;
}

}  // namespace allanlot::io
