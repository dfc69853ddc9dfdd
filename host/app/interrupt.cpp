#include "host/app/interrupt.h"

#include <csignal>
#include <cstring>

#include <unistd.h>

namespace pd {

namespace {

volatile std::sig_atomic_t g_signal = 0;
struct sigaction g_previous_int, g_previous_term;

// Async-signal-safe: records the signal, says so with write(2), and lets a second signal take
// the default action.
extern "C" void on_interrupt(int sig) {
  g_signal = sig;
  static const char kMsg[] =
      "\nperifrac: interrupted; finishing this frame and writing a checkpoint (again to stop now)\n";
  [[maybe_unused]] const ssize_t w = ::write(STDERR_FILENO, kMsg, sizeof kMsg - 1);
  struct sigaction dfl;
  std::memset(&dfl, 0, sizeof dfl);
  dfl.sa_handler = SIG_DFL;
  ::sigaction(sig, &dfl, nullptr);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_signal = 0;
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, &g_previous_int);
  ::sigaction(SIGTERM, &sa, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  ::sigaction(SIGINT, &g_previous_int, nullptr);
  ::sigaction(SIGTERM, &g_previous_term, nullptr);
}

int InterruptGuard::signal_received() {
  return g_signal;
}

}  // namespace pd
