#include "io/atomic_file.hpp"

#include "io/error.hpp"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <sys/file.h>
#include <unistd.h>

namespace allanlot::io {
namespace {

std::atomic<unsigned> g_counter{0};

void fsync_path(const std::filesystem::path& p, bool directory, const std::string& what) {
  const int fd = ::open(p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) throw Error(what, "", std::string("open for fsync: ") + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw Error(what, "", std::string("fsync: ") + std::strerror(err));
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
  // Hidden, and unique per host, process and call: two processes writing the same OUTDIR
  // never share a temporary file, also not Slurm tasks on different nodes of a shared file
  // system that happen to have the same pid; `summarize` skips names starting with '.'.
  std::string tail = ".tmp.";
  tail += host_tag();
  tail += '.';
  tail += std::to_string(::getpid());
  tail += '.';
  tail += std::to_string(g_counter++);
  // A name is at most 255 bytes (NAME_MAX): a long final name (a 240-character device_id) is
  // cut, with a hash of the whole name so that two long names still differ.
  std::string stem = final_.filename().string();
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
  temp_ = final_.parent_path() / name;
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::sync() {
  if (synced_) return;
  fsync_path(temp_, false, final_.string());
  synced_ = true;
}

void AtomicFile::commit() {
  try {
    sync();
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
    if (!committed_) {
      std::error_code ec;
      std::filesystem::remove(temp_, ec);
    }
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
  const std::string path = f.final_path().string();
  std::ofstream out(f.temp_path(), std::ios::binary | std::ios::trunc);
  if (!out) throw Error(path, "", "cannot create file: " + std::string(std::strerror(errno)));
  out << text;
  out.close();  // a write that fails only when the buffer is flushed at close (a full disk)
  if (!out) throw Error(path, "", std::string("write: ") + std::strerror(errno));
}

void write_text_atomic(const std::filesystem::path& path, const std::string& text) {
  // A character device or a pipe (`-o /dev/null`, `-o /dev/stdout`, a named pipe) is written
  // through: it holds no file to leave half-written.
  std::error_code ec;
  const auto type = std::filesystem::status(path, ec).type();
  if (!ec &&
      (type == std::filesystem::file_type::character || type == std::filesystem::file_type::fifo)) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error(path.string(), "", "cannot open: " + std::string(std::strerror(errno)));
    out << text;
    out.close();
    if (!out) throw Error(path.string(), "", std::string("write: ") + std::strerror(errno));
    return;
  }
  AtomicFile f(path);
  write_text(f, text);
  f.commit();
}

}  // namespace allanlot::io
