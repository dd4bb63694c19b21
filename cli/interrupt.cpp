#include "interrupt.h"

#include <signal.h>

namespace epsray {

namespace {

volatile sig_atomic_t received = 0;

// Async-signal-safe: one store.
void note(int s) { received = s; }

}  // namespace

void catch_interrupts() {
  struct sigaction sa = {};
  sa.sa_handler = note;
  sigemptyset(&sa.sa_mask);
  // SA_RESTART: writes and waits carry on rather than fail with EINTR; SA_RESETHAND: the
  // next signal takes the default action.
  sa.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return received; }

const char* signal_name(int s) { return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace epsray
