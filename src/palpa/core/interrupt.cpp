#include "palpa/core/interrupt.hpp"

#include <csignal>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {
// The one piece of process-wide mutable state palpa has: a signal can only
// communicate through a lock-free flag.
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void palpa_on_signal(int sig) {
  if (g_interrupted != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_interrupted = 1;
}
}  // namespace

void install_interrupt_handlers() {
  std::signal(SIGINT, palpa_on_signal);
  std::signal(SIGTERM, palpa_on_signal);
}

bool interrupt_requested() noexcept { return g_interrupted != 0; }

void check_interrupt() {
  if (g_interrupted != 0) {
    throw Error(ErrorKind::Interrupted, "interrupted");
  }
}

void request_interrupt() noexcept { g_interrupted = 1; }
void clear_interrupt() noexcept { g_interrupted = 0; }

}  // namespace palpa
