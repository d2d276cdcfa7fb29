#pragma once
// An exclusive lock on a byte range of a lock file, shared by processes on one machine or on a
// farm's shared disk: open-file-description locks (fcntl F_OFD_SETLK), which the kernel drops
// when the holder dies, which NFS carries between hosts (flock does not), and which let renders
// of disjoint frame ranges hold one output's lock file at the same time. The holder writes
// "pid host" at the start of its range, for a refused process to name it.
#include <sys/types.h>

#include <optional>
#include <string>

#include "util/interrupt.h"

namespace pluvia {

// Who holds a range another process asked for.
struct LockConflict {
  std::string holder;  // "pid host", or "unknown"
  off_t start = 0;     // the holder's range; length 0: to the end of the file (all of it)
  off_t length = 0;
};

class FileRangeLock {
 public:
  // Locks [start, start + length) of the file at `path` (length 0: the whole file), creating it
  // (and its folder) when missing. nullopt, with `conflict` filled, when another process holds
  // an overlapping range; throws pluvia::Error naming the file when it cannot be created or
  // locked at all. The lock counts only on the file at `path` now: a file removed by its last
  // holder between the open and the lock is opened again.
  static std::optional<FileRangeLock> tryLock(const std::string& path, off_t start, off_t length,
                                              LockConflict* conflict);
  FileRangeLock(FileRangeLock&& other) noexcept;
  FileRangeLock& operator=(FileRangeLock&&) = delete;
  FileRangeLock(const FileRangeLock&) = delete;
  ~FileRangeLock();

  const std::string& path() const { return path_; }

 private:
  FileRangeLock(std::string path, int fd)
      : path_(std::move(path)), fd_(fd), removedOnHardStop_(path_, fd_) {}
  std::string path_;
  int fd_ = -1;
  RemovedOnHardStop removedOnHardStop_;
};

// This machine's host name, as lock files record it.
std::string thisHostName();

}  // namespace pluvia
