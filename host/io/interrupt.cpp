#include "host/io/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <string>

#include <unistd.h>

namespace pd {

namespace {

// Read by other threads than the handler's (the renderer's stop question, the output writers).
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);  // (so the handler may store it)
struct sigaction g_previous_int, g_previous_term;

// Async-signal-safe: records the signal, says so with write(2), and lets a second signal, of
// either kind, take the default action.
extern "C" void on_interrupt(int sig) {
  g_signal = sig;
  static const char kMsg[] =
      "\nperifrac: interrupted; stopping at the next safe point (again to stop at once)\n";
  [[maybe_unused]] const ssize_t w = ::write(STDERR_FILENO, kMsg, sizeof kMsg - 1);
  struct sigaction dfl;
  std::memset(&dfl, 0, sizeof dfl);
  dfl.sa_handler = SIG_DFL;
  ::sigaction(SIGINT, &dfl, nullptr);
  ::sigaction(SIGTERM, &dfl, nullptr);
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
  if (const int sig = g_signal; sig != 0)
    throw Interrupted(std::string("interrupted during ") + where + " (" +
                      (sig == SIGTERM ? "SIGTERM" : "SIGINT") + ")");
}

}  // namespace pd
