#pragma once
// Stopping cleanly on SIGINT, SIGTERM and SIGHUP. The handler only records the signal; long jobs
// check it between frames and throw Interrupted, which unwinds like any error, so temporary files
// and a movie's partial file are removed on the way out. The command then exits 128 + the signal
// (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP). Every frame a clip reader reads checks it
// too, so a per-clip analysis (prepare, derain) stops at its next frame. A second signal acts at
// once (the default action).
#include "util/error.h"

namespace pluvia {

class Interrupted : public Error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Installs the handlers for its lifetime (only jobs that check interruptSignal() should).
class InterruptHandlers {
 public:
  InterruptHandlers();
  ~InterruptHandlers();
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;
};

// The signal that arrived (SIGINT, SIGTERM, SIGHUP), or 0.
int interruptSignal();
// Throws Interrupted when a signal arrived.
void throwIfInterrupted();

}  // namespace pluvia
