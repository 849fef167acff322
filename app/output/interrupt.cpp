#include "app/output/interrupt.h"

#include <signal.h>

#include <csignal>

namespace wobble {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void onSignal(int signal) {
  if (received == 0) received = signal;
}

}  // namespace

void installInterruptHandlers() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // file I/O carries on; the loops poll interrupted()
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    return true;
  }();
  (void)installed;
}

int interruptSignal() { return received; }

int exitStatusAfterSignals(int status) {
  if (received == SIGINT) return kExitInterrupted;
  if (received == SIGTERM) return kExitTerminated;
  return status;
}

}  // namespace wobble
