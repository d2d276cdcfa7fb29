#include "util/file_lock.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "util/error.h"
#include "util/fs.h"
#include "util/input_guard.h"
#include "util/log.h"

namespace pluvia {
namespace {

// The holder's text: at most this many bytes at the start of its range.
constexpr size_t kHolderBytes = 64;

struct flock writeLock(off_t start, off_t length) {
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = start;
  lock.l_len = length;
  return lock;
}

std::string holderAt(int fd, off_t offset) {
  char text[kHolderBytes + 1] = {};
  const ssize_t n = pread(fd, text, kHolderBytes, offset);
  std::string holder = n > 0 ? std::string(text, strnlen(text, static_cast<size_t>(n))) : "";
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
  return holder.empty() ? "unknown" : holder;
}

bool isFileAtPath(int fd, const std::string& path) {
  struct stat opened {
  }, current{};
  return fstat(fd, &opened) == 0 && stat(path.c_str(), &current) == 0 &&
         opened.st_ino == current.st_ino && opened.st_dev == current.st_dev;
}

}  // namespace

std::string thisHostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown-host";
  return name;
}

std::optional<FileRangeLock> FileRangeLock::tryLock(const std::string& path, off_t start,
                                                    off_t length, LockConflict* conflict) {
  fs::ensureParentFolder(path, fs::MakeFolders::All);
  // The lock's bytes are written and the file removed by its last holder: never an input.
  fs::refuseWritingInput(path);
  while (true) {
    // Never through a link: a lock file that is a symlink (or a second name of another file)
    // would have its target's bytes overwritten by the holder's pid and host.
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == ELOOP)
      throw Error(fmt::format("the lock file {} is a symbolic link: refusing to follow it (remove "
                              "it; pluvia makes its own)",
                              path),
                  {{}, {}, path});
    if (fd < 0)
      throw Error(fmt::format("cannot create the lock file {}: {}", path, std::strerror(errno)),
                  {{}, {}, path});
    struct stat opened {};
    if (fstat(fd, &opened) == 0 && opened.st_nlink == 0) {  // removed by its last holder
      ::close(fd);
      continue;
    }
    if (fstat(fd, &opened) != 0 || !S_ISREG(opened.st_mode) || opened.st_nlink != 1) {
      ::close(fd);
      throw Error(fmt::format("the lock file {} is not a plain file of its own (a device, a "
                              "folder or a hard link to another file): refusing to write to it",
                              path),
                  {{}, {}, path});
    }
    struct flock lock = writeLock(start, length);
    if (fcntl(fd, F_OFD_SETLK, &lock) != 0) {
      const int failure = errno;
      if (failure != EAGAIN && failure != EACCES) {
        ::close(fd);
        throw Error(fmt::format("cannot lock {}: {}", path, std::strerror(failure)),
                    {{}, {}, path});
      }
      struct flock held = writeLock(start, length);
      if (conflict) {
        *conflict = LockConflict{};
        // The holder may have let go since: then nothing is named.
        if (fcntl(fd, F_OFD_GETLK, &held) == 0 && held.l_type != F_UNLCK) {
          conflict->holder = holderAt(fd, held.l_start);
          conflict->start = held.l_start;
          conflict->length = held.l_len;
        } else {
          conflict->holder = "unknown";
        }
      }
      ::close(fd);
      return std::nullopt;
    }
    if (!isFileAtPath(fd, path)) {  // removed by its last holder meanwhile
      ::close(fd);
      continue;
    }
    std::string text = fmt::format("{} {}\n", getpid(), thisHostName());
    text.resize(kHolderBytes, '\0');
    text.back() = '\0';
    // The lock holds without its text; only a refused process's message is the poorer.
    if (pwrite(fd, text.data(), text.size(), start) != static_cast<ssize_t>(text.size()))
      log::warning("cannot write the pid and host into the lock file " + path);
    return FileRangeLock(path, fd);
  }
}

FileRangeLock::FileRangeLock(FileRangeLock&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(other.fd_),
      removedOnHardStop_(std::move(other.removedOnHardStop_)) {
  other.fd_ = -1;
}

FileRangeLock::~FileRangeLock() {
  removedOnHardStop_.release();  // before the descriptor closes and its number is reused
  if (fd_ < 0) return;
  // The last holder removes the file, while it holds all of it, so no process can hold a lock
  // on a removed file unnoticed (tryLock checks that its file is still at the path). Others
  // leave it to the last.
  struct flock whole = writeLock(0, 0);
  if (fcntl(fd_, F_OFD_SETLK, &whole) == 0) ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace pluvia
