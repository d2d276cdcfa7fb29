#pragma once
// Stopping cleanly on SIGINT, SIGTERM and SIGHUP. The handler only records the signal; long jobs
// check it between frames and throw Interrupted, which unwinds like any error, so temporary files
// and a movie's partial file are removed on the way out. The command then exits 128 + the signal
// (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP). Every frame a clip reader reads checks it
// too, so a per-clip analysis (prepare, derain) stops at its next frame. A second signal stops
// the process at once, exit 128 + the signal, after removing its locks and temporaries
// (RemovedOnHardStop).
#include <string>

#include "util/error.h"

namespace pluvia {

class Interrupted : public Error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

// A file the process removes when a second signal stops it at once: a lock (with `lockFd`, its
// open descriptor: removed only where no other process holds a part of it, as FileRangeLock's
// last holder does) or a temporary being written. Registered for the object's lifetime, in a
// fixed table the signal handler reads without allocating (best effort: past 256 files at once,
// the others are not registered).
class RemovedOnHardStop {
 public:
  explicit RemovedOnHardStop(const std::string& path, int lockFd = -1);
  RemovedOnHardStop(RemovedOnHardStop&& other) noexcept;
  RemovedOnHardStop& operator=(RemovedOnHardStop&&) = delete;
  RemovedOnHardStop(const RemovedOnHardStop&) = delete;
  ~RemovedOnHardStop();
  // No longer removed on a hard stop (before the file is released another way).
  void release();

 private:
  int slot_ = -1;
};

// A child process a second signal kills (SIGKILL) and reaps before the files are removed, so
// that it cannot write one after the process is gone (ffmpeg creates its output only once the
// first frames arrive). Registered for the object's lifetime, in the same table.
class KilledOnHardStop {
 public:
  explicit KilledOnHardStop(int pid);
  KilledOnHardStop(const KilledOnHardStop&) = delete;
  KilledOnHardStop& operator=(const KilledOnHardStop&) = delete;
  ~KilledOnHardStop();

 private:
  int slot_ = -1;
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
