#include "util/interrupt.h"

#include <csignal>

namespace pluvia {
namespace {

volatile std::sig_atomic_t gSignal = 0;

void record(int signal) {
  gSignal = signal;
}

struct sigaction gPreviousInt, gPreviousTerm, gPreviousHup;

}  // namespace

Interrupted::Interrupted(int signal)
    : Error(std::string("stopped by ") +
            (signal == SIGINT   ? "SIGINT"
             : signal == SIGHUP ? "SIGHUP"
                                : "SIGTERM") +
            "; frames already written are whole, nothing partial is left"),
      signal_(signal) {}

InterruptHandlers::InterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = record;
  sigemptyset(&action.sa_mask);
  // SA_RESETHAND: a second Ctrl-C stops a job that does not reach its next check.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(SIGINT, &action, &gPreviousInt);
  sigaction(SIGTERM, &action, &gPreviousTerm);
  // A closed terminal or ssh session hangs the job up: it stops as cleanly as on SIGTERM.
  sigaction(SIGHUP, &action, &gPreviousHup);
}

InterruptHandlers::~InterruptHandlers() {
  sigaction(SIGINT, &gPreviousInt, nullptr);
  sigaction(SIGTERM, &gPreviousTerm, nullptr);
  sigaction(SIGHUP, &gPreviousHup, nullptr);
}

int interruptSignal() {
  return gSignal;
}

void throwIfInterrupted() {
  if (const int signal = gSignal) throw Interrupted(signal);
}

}  // namespace pluvia
