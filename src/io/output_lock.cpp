#include "io/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "io/sequence_pattern.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia {
namespace {

std::string thisHost() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown-host";
  return name;
}

// What the holder wrote ("pid host"), or a note when the file cannot be read.
std::string holderOf(int fd) {
  char text[512] = {};
  const ssize_t n = pread(fd, text, sizeof text - 1, 0);
  std::string holder = n > 0 ? std::string(text, static_cast<size_t>(n)) : "";
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
  return holder.empty() ? "unknown" : holder;
}

}  // namespace

std::string outputLockPath(const std::string& output) {
  if (std::optional<SequencePattern> pattern = SequencePattern::parse(output)) {
    const size_t digits = static_cast<size_t>(std::max(pattern->padding, 1));
    return pattern->prefix + std::string(digits, '#') + pattern->suffix + ".pluvia-lock";
  }
  return output + ".pluvia-lock";
}

OutputLock::OutputLock(const std::string& output) : path_(outputLockPath(output)) {
  const ErrorContext context{"write", {}, output};
  fs::ensureParentFolder(path_);
  while (true) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      throw Error(fmt::format("cannot create the lock file {}: {}", path_, std::strerror(errno)),
                  context);
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int failure = errno;
      const std::string holder = holderOf(fd_);
      ::close(fd_);
      fd_ = -1;
      if (failure == EWOULDBLOCK) {
        throw Error(fmt::format("another render (pid and host: {}) is writing {}; wait for it "
                                "or write elsewhere (lock file {})",
                                holder, output, path_),
                    context);
      }
      throw Error(fmt::format("cannot lock {}: {}", path_, std::strerror(failure)), context);
    }
    // The holder we waited on may have removed the file between our open and our lock: the lock
    // counts only on the file that is at the path now.
    struct stat locked {
    }, current{};
    if (fstat(fd_, &locked) == 0 && stat(path_.c_str(), &current) == 0 &&
        locked.st_ino == current.st_ino && locked.st_dev == current.st_dev) {
      break;
    }
    ::close(fd_);
    fd_ = -1;
  }
  const std::string holder = fmt::format("{} {}\n", getpid(), thisHost());
  const bool described = ftruncate(fd_, 0) == 0 && pwrite(fd_, holder.data(), holder.size(), 0) ==
                                                       static_cast<ssize_t>(holder.size());
  // The lock holds without its text; only a refused render's message is the poorer.
  if (!described) log::warning("cannot write the pid and host into the lock file " + path_);
}

OutputLock::~OutputLock() {
  // Removed while still locked, so no other render can hold a lock on the removed file.
  ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace pluvia
