#include "io/isolation.hpp"

#include "io/error.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <new>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

// AddressSanitizer and ThreadSanitizer reserve terabytes of address space for their shadow
// memory: under them the child's address space cannot be bounded (its CPU and wall time are).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ALLANLOT_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define ALLANLOT_SANITIZED 1
#endif
#endif

namespace allanlot::io {
namespace {

bool g_in_child = false;

// Exit statuses of the child: what it tells the parent beside the message on the pipe.
constexpr int kChildOk = 0;
constexpr int kChildError = 3;     // an io::Error: "<dataset>\0<reason>" on the pipe
constexpr int kChildNoMemory = 4;  // std::bad_alloc under RLIMIT_AS

void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

#ifndef ALLANLOT_SANITIZED
// The address space this process maps now (/proc/self/statm's first field, in pages).
std::uint64_t mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}
#endif

void set_limit(int resource, std::uint64_t value) {
  const rlimit lim{static_cast<rlim_t>(value), static_cast<rlim_t>(value)};
  ::setrlimit(resource, &lim);
}

[[noreturn]] void child(int fd, const std::function<void()>& work, const IsolationLimits& limits) {
  g_in_child = true;
  // A crash here is expected of hostile files: it ends the child as the signal's default does,
  // without a core dump, and without the handlers the parent installed (a sanitizer's report,
  // libFuzzer's crash artifact), which belong to the parent's own faults.
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
    std::signal(sig, SIG_DFL);
  set_limit(RLIMIT_CORE, 0);
  set_limit(RLIMIT_CPU, static_cast<std::uint64_t>(limits.cpu.count()));
#ifndef ALLANLOT_SANITIZED
  set_limit(RLIMIT_AS, mapped_bytes() + limits.extra_address_space);
#endif
  int status = kChildOk;
  try {
    work();
  } catch (const Error& e) {
    std::string msg = e.dataset();
    msg += '\0';
    msg += e.reason();
    write_all(fd, msg);
    status = kChildError;
  } catch (const std::bad_alloc&) {
    status = kChildNoMemory;
  } catch (const std::exception& e) {
    std::string msg(1, '\0');
    msg += e.what();
    write_all(fd, msg);
    status = kChildError;
  }
  ::close(fd);
  ::_exit(status);  // no atexit handlers, no flush of the parent's buffered output
}

// Reads the child's message until the pipe closes or `wall` has passed; false on the timeout.
bool read_message(int fd, std::chrono::seconds wall, std::string& msg) {
  const auto deadline = std::chrono::steady_clock::now() + wall;
  char buf[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd, POLLIN, 0};
    const int rc = ::poll(&p, 1, static_cast<int>(left.count()));
    if (rc < 0 && errno == EINTR) continue;
    if (rc <= 0) return rc < 0;  // an error of poll itself: treated as the pipe's end
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    if (msg.size() < (std::size_t{1} << 16)) msg.append(buf, static_cast<std::size_t>(n));
  }
}

std::string signal_text(int sig) {
  const char* name = ::strsignal(sig);
  return "signal " + std::to_string(sig) + (name ? std::string(", ") + name : std::string());
}

[[noreturn]] void child_failed(const std::string& file, int status, bool timed_out,
                               const IsolationLimits& limits, const std::string& msg) {
  const std::string damaged = ": the file is damaged or not a valid HDF5 file";
  if (timed_out)
    throw Error(file, "",
                "reading its HDF5 metadata took more than " + std::to_string(limits.wall.count()) +
                    " s" + damaged);
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
    throw Error(file, "",
                "reading its HDF5 metadata took more than " + std::to_string(limits.cpu.count()) +
                    " s of CPU time" + damaged);
  if (WIFSIGNALED(status))
    throw Error(file, "",
                "the HDF5 library crashed reading its metadata (" + signal_text(WTERMSIG(status)) +
                    ")" + damaged);
  const int code = WEXITSTATUS(status);
  if (code == kChildError) {
    const auto nul = msg.find('\0');
    if (nul != std::string::npos) throw Error(file, msg.substr(0, nul), msg.substr(nul + 1));
  }
  if (code == kChildNoMemory)
    throw Error(file, "",
                "reading its HDF5 metadata needs more than " +
                    std::to_string(limits.extra_address_space >> 20) + " MiB of memory" + damaged);
  throw Error(file, "",
              "the HDF5 library failed reading its metadata (exit status " + std::to_string(code) +
                  ")" + damaged);
}

}  // namespace

bool in_isolated_child() {
  return g_in_child;
}

void read_in_process() {
  g_in_child = true;
}

void run_isolated(const std::string& file, const std::function<void()>& work,
                  const IsolationLimits& limits) {
  if (g_in_child) {
    work();
    return;
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error(file, "",
                std::string("cannot start the process that reads it: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error(file, "",
                std::string("cannot start the process that reads it: ") + std::strerror(err));
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], work, limits);
  }
  ::close(fds[1]);
  std::string msg;
  const bool timed_out = !read_message(fds[0], limits.wall, msg);
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!timed_out && WIFEXITED(status) && WEXITSTATUS(status) == kChildOk) return;
  child_failed(file, status, timed_out, limits, msg);
}

}  // namespace allanlot::io
