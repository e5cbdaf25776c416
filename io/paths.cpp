#include "io/paths.hpp"

#include "io/atomic_file.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
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
  // By identity (a link, another spelling) and by canonical name (an input that vanished
  // since it was listed is still not to be replaced).
  std::error_code ec;
  const fs::path out_name = fs::weakly_canonical(output, ec);
  for (const fs::path& in : inputs) {
    if (same_file(output, in)) return in;
    std::error_code ec_in;
    if (!ec && fs::weakly_canonical(in, ec_in) == out_name && !ec_in) return in;
  }
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

namespace {

// io::AtomicFile's names: '.', the final name (cut to fit), ".tmp.", host, '.', pid, '.', a
// random tag of hex digits.
// Returns the host and pid of such a name, or nullopt. (Parsed by hand: libstdc++'s <regex>
// trips GCC 12's -Wmaybe-uninitialized under ASan.)
std::optional<std::pair<std::string, long>> temporary_writer(const std::string& name) {
  const auto tmp = name.rfind(".tmp.");
  if (!name.starts_with(".") || tmp == std::string::npos || tmp == 0) return std::nullopt;
  const std::string tail = name.substr(tmp + 5);
  const auto dot2 = tail.rfind('.');
  const auto dot1 =
      dot2 == std::string::npos || dot2 == 0 ? std::string::npos : tail.rfind('.', dot2 - 1);
  if (dot1 == std::string::npos) return std::nullopt;
  const std::string host = tail.substr(0, dot1);
  const std::string pid = tail.substr(dot1 + 1, dot2 - dot1 - 1);
  const std::string n = tail.substr(dot2 + 1);
  const auto digits = [](const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
  };
  const bool host_ok = std::all_of(host.begin(), host.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || c == '-' || c == '_';
  });
  const bool tag_ok = !n.empty() && std::all_of(n.begin(), n.end(), [](unsigned char c) {
    return std::isxdigit(c) != 0;
  });
  if (pid.size() > 9 || !digits(pid) || !tag_ok || !host_ok) return std::nullopt;
  return std::pair{host, std::stol(pid)};
}

}  // namespace

std::size_t remove_stale_temporaries(const fs::path& dir, fs::file_time_type before) {
  const std::string this_host = host_tag();
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const auto writer = temporary_writer(e.path().filename().string());
    if (!writer || !e.is_regular_file(ec)) continue;
    if (e.last_write_time(ec) >= before || ec) continue;
    // A writer on this host that is still alive (another run) keeps its file.
    const auto pid = static_cast<pid_t>(writer->second);
    if (writer->first == this_host && (::kill(pid, 0) == 0 || errno == EPERM)) continue;
    if (fs::remove(e.path(), ec)) ++removed;
  }
  return removed;
}

}  // namespace allanlot::io
