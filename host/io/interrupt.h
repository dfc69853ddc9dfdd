// SIGINT / SIGTERM while a command works: the first asks it to stop at its next safe point (the
// run's frame loop writes a checkpoint first; its set-up and `render` stop between stages or
// frames, leaving only complete files); a second one ends the process at once (the default
// action). Without a guard installed the signals keep their default action.
#pragma once

#include <stdexcept>

namespace pd {

// Thrown by throw_if_interrupted: a command asked to stop, at a point where nothing is half-written.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

// Throws Interrupted ("interrupted during <where>") when a guard has received a signal.
void throw_if_interrupted(const char* where);

}  // namespace pd
