// SIGINT and SIGTERM during render and walk: the handler only notes the signal, and the
// commands look between frames, so that outputs are finished or abandoned whole and
// temporaries never stay behind.
#pragma once

namespace epsray {

// Installs the handlers. After the first SIGINT (or SIGTERM), a second of the same kind
// ends the process at once, for a user who will not wait for the frame in hand.
void catch_interrupts();
// The signal received since catch_interrupts (SIGINT or SIGTERM), or 0.
int interrupt_signal();
// "SIGINT" or "SIGTERM", for messages.
const char* signal_name(int s);
// The shell's exit code for a run ended by signal s: 128 + s (130 for SIGINT, 143 for SIGTERM).
inline int interrupted_exit_code(int s) { return 128 + s; }

}  // namespace epsray
