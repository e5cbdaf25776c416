#include "src/cli/interrupt.hpp"

#include <csignal>
#include <cstdio>

namespace allanlot::cli {
namespace {

volatile std::sig_atomic_t g_signal = 0;
struct sigaction g_previous_int {};
struct sigaction g_previous_term {};

// Only records the signal: async-signal-safe (POSIX allows writing a volatile sig_atomic_t).
// SA_RESETHAND restores the default action, so a second signal ends the process.
extern "C" void record_signal(int sig) {
  g_signal = sig;
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = record_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &sa, &g_previous_int);
  sigaction(SIGTERM, &sa, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int stop_signal() {
  return g_signal;
}

const char* signal_name(int sig) {
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  static char name[32];
  std::snprintf(name, sizeof name, "signal %d", sig);
  return name;
}

}  // namespace allanlot::cli
