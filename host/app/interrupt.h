// SIGINT / SIGTERM during a run: the first asks the frame loop to finish the frame, write a
// checkpoint and stop; a second one ends the process at once (the default action).
#pragma once

namespace pd {

// Installs the handlers for the lifetime of the object and restores the previous ones after.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // The signal received (SIGINT or SIGTERM), 0 if none.
  static int signal_received();
};

}  // namespace pd
