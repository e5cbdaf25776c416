#include "io/atomic_file.hpp"

#include "io/error.hpp"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <functional>
#include <sys/file.h>
#include <sys/random.h>
#include <unistd.h>

namespace allanlot::io {
namespace {

std::atomic<std::uint64_t> g_counter{0};

void fsync_path(const std::filesystem::path& p, bool directory, const std::string& what) {
  const int fd = ::open(p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) throw Error(what, "", std::string("open for fsync: ") + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw Error(what, "", std::string("fsync: ") + std::strerror(err));
}

// 64 bits nobody else can predict (getrandom(2)); should the kernel refuse, a mix of the time,
// the pid and a counter, which O_EXCL still keeps from being pre-empted unnoticed.
std::string random_tag() {
  std::uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r))
    r = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
        (static_cast<std::uint64_t>(::getpid()) << 32) ^ g_counter++;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(r));
  return hex;
}

// `.<name>.tmp.<host>.<pid>.<random>` beside `final_path`: hidden (`summarize` skips names
// starting with '.'), and with the writer's host and pid for the clean-up of an interrupted
// run (io/paths.hpp).
std::filesystem::path temporary_name(const std::filesystem::path& final_path) {
  std::string tail = ".tmp.";
  tail += host_tag();
  tail += '.';
  tail += std::to_string(::getpid());
  tail += '.';
  tail += random_tag();
  // A name is at most 255 bytes (NAME_MAX): a long final name (a 240-character device_id) is
  // cut, with a hash of the whole name so that two long names still differ.
  std::string stem = final_path.filename().string();
  constexpr std::size_t kNameMax = 255;
  if (1 + stem.size() + tail.size() > kNameMax) {
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016zx", std::hash<std::string>{}(stem));
    stem.resize(kNameMax - 1 - tail.size() - 17);
    stem += '~';
    stem += hash;
  }
  // Appended piece by piece: `"." + std::string` trips GCC 12's -Wrestrict false positive
  // (GCC bug 105651).
  std::string name(1, '.');
  name += stem;
  name += tail;
  return final_path.parent_path() / name;
}

}  // namespace

std::string host_tag() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  std::string h;
  for (const char* c = host; *c; ++c)
    h += std::isalnum(static_cast<unsigned char>(*c)) || *c == '-' ? *c : '_';
  return h;
}

AtomicFile::AtomicFile(std::filesystem::path final_path) : final_(std::move(final_path)) {
  // O_EXCL and O_NOFOLLOW: a file or a symbolic link planted under the name makes open fail
  // instead of being written through; a new random name is then tried.
  for (int attempt = 0; attempt < 8 && fd_ < 0; ++attempt) {
    temp_ = temporary_name(final_);
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) break;
  }
  if (fd_ < 0)
    throw Error(final_.string(), "",
                std::string("cannot create a temporary file beside it: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(temp_.c_str());
}

void AtomicFile::write(const char* bytes, std::size_t n) const {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = fd_ < 0 ? -1 : ::write(fd_, bytes + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const int err = w < 0 ? (fd_ < 0 ? EBADF : errno) : ENOSPC;
      throw Error(final_.string(), "", std::string("write: ") + std::strerror(err));
    }
    done += static_cast<std::size_t>(w);
  }
}

void AtomicFile::sync() {
  if (synced_) return;
  if (fd_ < 0 || ::fsync(fd_) != 0)
    throw Error(final_.string(), "", std::string("fsync: ") + std::strerror(errno));
  synced_ = true;
}

void AtomicFile::commit() {
  try {
    sync();
    // Some file systems (NFS) report a failed write only at close.
    const int rc = ::close(fd_);
    fd_ = -1;
    if (rc != 0) throw Error(final_.string(), "", std::string("close: ") + std::strerror(errno));
    std::error_code ec;
    // A device, pipe or directory under the final name is never replaced: renamed over as
    // root, `-o /dev/null` had made /dev/null a regular file in /dev, which then filled up.
    const auto st = std::filesystem::status(final_, ec);
    if (!ec && st.type() != std::filesystem::file_type::regular)
      throw Error(final_.string(), "", "not a regular file, so not replaced");
    ec.clear();
    std::filesystem::rename(temp_, final_, ec);
    if (ec) throw Error(final_.string(), "", "rename from temporary file: " + ec.message());
    committed_ = true;
    const auto dir =
        final_.parent_path().empty() ? std::filesystem::path(".") : final_.parent_path();
    fsync_path(dir, true, final_.string());
  } catch (...) {
    if (!committed_) ::unlink(temp_.c_str());
    throw;
  }
}

DirectoryLock::DirectoryLock(const std::filesystem::path& directory) {
  fd_ = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) return;
  int rc = 0;
  while ((rc = ::flock(fd_, LOCK_EX)) != 0 && errno == EINTR) {
  }
  if (rc != 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

void commit_together(std::initializer_list<AtomicFile*> files) {
  for (AtomicFile* f : files)
    f->sync();
  for (AtomicFile* f : files)
    f->commit();
}

void write_text(const AtomicFile& f, const std::string& text) {
  f.write(text.data(), text.size());
}

void write_text_atomic(const std::filesystem::path& path, const std::string& text) {
  // A character device or a pipe (`-o /dev/null`, `-o /dev/stdout`, a named pipe) is written
  // through: it holds no file to leave half-written.
  std::error_code ec;
  const auto type = std::filesystem::status(path, ec).type();
  if (!ec &&
      (type == std::filesystem::file_type::character || type == std::filesystem::file_type::fifo)) {
    // O_NONBLOCK: a named pipe nobody reads fails at once (ENXIO) instead of blocking for ever;
    // the writes themselves then block as usual.
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
      throw Error(path.string(), "",
                  errno == ENXIO ? std::string("a named pipe that nobody reads")
                                 : "cannot open: " + std::string(std::strerror(errno)));
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int err = n < 0 ? errno : ENOSPC;
        ::close(fd);
        throw Error(path.string(), "", std::string("write: ") + std::strerror(err));
      }
      done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0)
      throw Error(path.string(), "", std::string("write: ") + std::strerror(errno));
    return;
  }
  AtomicFile f(path);
  write_text(f, text);
  f.commit();
}

}  // namespace allanlot::io
