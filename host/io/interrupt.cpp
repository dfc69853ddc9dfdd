#include "host/io/interrupt.h"

#include <csignal>
#include <cstring>
#include <string>

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
      "\nperifrac: interrupted; stopping at the next safe point (again to stop at once)\n";
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
  g_signal = 0;
}

int InterruptGuard::signal_received() {
  return g_signal;
}

void throw_if_interrupted(const char* where) {
  if (g_signal != 0)
    throw Interrupted(std::string("interrupted during ") + where + " (" +
                      (g_signal == SIGTERM ? "SIGTERM" : "SIGINT") + ")");
}

}  // namespace pd
