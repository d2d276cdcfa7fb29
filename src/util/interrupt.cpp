#include "util/interrupt.h"

#include <fcntl.h>
#include <limits.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace pluvia {
namespace {

volatile std::sig_atomic_t gSignal = 0;

// The files RemovedOnHardStop and the children KilledOnHardStop register. A slot is free, being
// written (skipped by the handler) or ready; the handler reads ready slots only, with
// async-signal-safe calls.
constexpr int kSlots = 256;
enum SlotState : int { kFree = 0, kWriting = 1, kReady = 2 };
struct Slot {
  std::atomic<int> state{kFree};
  std::atomic<unsigned> generation{0};  // counts registrations: a slot reused is seen
  int lockFd = -1;
  pid_t child = -1;  // a child process to kill, or -1 for a file
  char path[PATH_MAX];
};
Slot gSlots[kSlots];

// A free slot marked being written, or -1 when all are taken.
int claimSlot() {
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!gSlots[i].state.compare_exchange_strong(expected, kWriting)) continue;
    gSlots[i].generation.fetch_add(1);
    return i;
  }
  return -1;
}

// The children first, killed and reaped: none can write a file once the files are removed.
void killRegisteredChildren() {
  for (Slot& slot : gSlots) {
    if (slot.state.load() != kReady) continue;
    const pid_t child = slot.child;
    if (child <= 0 || slot.state.load() != kReady) continue;
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
  }
}

void removeRegisteredFiles() {
  // Other threads run on while this one handles the signal: a slot is read into a copy, and the
  // copy used only if the slot stayed ready and unchanged while it was made.
  static char path[PATH_MAX];
  for (Slot& slot : gSlots) {
    const unsigned generation = slot.generation.load();
    if (slot.state.load() != kReady) continue;
    if (slot.child > 0) continue;
    const int lockFd = slot.lockFd;
    std::memcpy(path, slot.path, PATH_MAX);
    if (slot.state.load() != kReady || slot.generation.load() != generation) continue;
    path[PATH_MAX - 1] = '\0';
    if (lockFd >= 0) {
      // As FileRangeLock's last holder: only a lock file no other process holds a part of.
      struct flock whole {};
      whole.l_type = F_WRLCK;
      whole.l_whence = SEEK_SET;
      if (fcntl(lockFd, F_OFD_SETLK, &whole) != 0) continue;
    }
    ::unlink(path);
  }
}

void record(int signal) {
  if (gSignal != 0) {
    // The second signal: the job did not reach its next check; stop now, leaving nothing.
    killRegisteredChildren();
    removeRegisteredFiles();
    _exit(128 + signal);
  }
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
  // A second Ctrl-C stops a job that does not reach its next check (record()).
  action.sa_flags = SA_RESTART;
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

RemovedOnHardStop::RemovedOnHardStop(const std::string& path, int lockFd) {
  if (path.size() >= PATH_MAX || (slot_ = claimSlot()) < 0) return;
  gSlots[slot_].lockFd = lockFd;
  gSlots[slot_].child = -1;
  std::memcpy(gSlots[slot_].path, path.c_str(), path.size() + 1);
  gSlots[slot_].state.store(kReady);
}

KilledOnHardStop::KilledOnHardStop(int pid) {
  if (pid <= 0 || (slot_ = claimSlot()) < 0) return;
  gSlots[slot_].lockFd = -1;
  gSlots[slot_].child = pid;
  gSlots[slot_].path[0] = '\0';
  gSlots[slot_].state.store(kReady);
}

KilledOnHardStop::~KilledOnHardStop() {
  if (slot_ >= 0) gSlots[slot_].state.store(kFree);
}

RemovedOnHardStop::RemovedOnHardStop(RemovedOnHardStop&& other) noexcept : slot_(other.slot_) {
  other.slot_ = -1;
}

RemovedOnHardStop::~RemovedOnHardStop() {
  release();
}

void RemovedOnHardStop::release() {
  if (slot_ < 0) return;
  gSlots[slot_].state.store(kFree);
  slot_ = -1;
}

int interruptSignal() {
  return gSignal;
}

void throwIfInterrupted() {
  if (const int signal = gSignal) throw Interrupted(signal);
}

}  // namespace pluvia
