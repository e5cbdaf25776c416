// SIGINT and SIGTERM during a long run (docs/reliability.md "Signals"): the first signal asks
// the run to stop at the next safe point (after the recording or unit in flight is complete),
// so that no temporary file is left behind, the lot summary covers what is done, and the exit
// status says which signal stopped it (128 + signal, as shells report a signal). A second
// signal ends the process at once with the default action; the temporary files it leaves are
// removed by the next run into the same OUTDIR (io::remove_stale_temporaries).
#pragma once

namespace allanlot::cli {

/// Installs the handlers for its lifetime and restores the previous ones after.
class InterruptGuard {
public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// 0 while no signal came, else the number of the signal that asked the run to stop.
int stop_signal();

/// "SIGINT" or "SIGTERM" (or "signal N").
const char* signal_name(int sig);

}  // namespace allanlot::cli
