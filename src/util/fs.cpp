#include "util/fs.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "util/error.h"
#include "util/input_guard.h"
#include "util/interrupt.h"

namespace pluvia::fs {
namespace stdfs = std::filesystem;

stdfs::path temporaryPathFor(const stdfs::path& target, size_t reserveBytes) {
  static std::atomic<uint64_t> counter{0};
  const std::string tail = ".pluvia-tmp-" + std::to_string(getpid()) + "-" +
                           std::to_string(counter++) + target.extension().string();
  // A legal name near the 255-byte limit must still get a temporary: its stem is cut short
  // (the start, which names the output, is kept).
  std::string stem = target.stem().string();
  const size_t room = kNameMaxBytes - std::min(kNameMaxBytes, tail.size() + reserveBytes);
  if (stem.size() > room) stem.resize(room);
  return target.parent_path() / (stem + tail);
}

void refuseSpecialTarget(const stdfs::path& target) {
  std::error_code ec;
  const stdfs::file_status status = stdfs::status(target, ec);
  if (!stdfs::exists(status) || stdfs::is_regular_file(status)) return;
  throw UsageError(target.string() + " is " +
                       (stdfs::is_directory(status) ? "a folder"
                        : stdfs::is_fifo(status)    ? "a FIFO"
                                                    : "a device or socket") +
                       ", not a file: pluvia writes its images and movies to files, and would "
                       "replace it",
                   {"write", {}, target.string()});
}

void commitTemporary(const stdfs::path& tmp, const stdfs::path& target) {
  std::error_code ec;
  try {
    refuseWritingInput(target);
    refuseSpecialTarget(target);
  } catch (const Error&) {
    stdfs::remove(tmp, ec);
    throw;
  }
  stdfs::rename(tmp, target, ec);
  if (ec) {
    const std::string why = ec.message();  // before remove() reuses ec
    stdfs::remove(tmp, ec);
    throw Error("cannot move the finished file into place: " + why, {"write", {}, target.string()});
  }
}

namespace {

// Writes all `size` bytes to `fd`; 0 or the errno of the failure.
int writeAll(int fd, const char* bytes, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    bytes += n;
    size -= static_cast<size_t>(n);
  }
  return 0;
}

// Writes, flushes and closes; returns 0 or the errno of the first step that failed.
int writeWholeFile(const stdfs::path& path, const char* bytes, size_t size) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  int failure = writeAll(fd, bytes, size);
  // A full disk may only show when the data is flushed, or on close (NFS).
  if (failure == 0 && ::fdatasync(fd) != 0) failure = errno;
  if (::close(fd) != 0 && failure == 0) failure = errno;
  return failure;
}

// Writes through to a FIFO or a character device (`--csv /dev/stdout`, `>(sort)`, /dev/null)
// rather than replacing it by a file; 0 or the errno of the failure (ENXIO: a FIFO nobody
// reads, which would block the run; ENOSPC: /dev/full).
int writeThrough(const stdfs::path& target, const char* bytes, size_t size) {
  const int fd = ::open(target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return errno;
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // a reader is there: wait for it
  int failure = writeAll(fd, bytes, size);
  if (::close(fd) != 0 && failure == 0) failure = errno;
  return failure;
}

}  // namespace

void writeFileAtomically(const stdfs::path& target, const void* bytes, size_t size) {
  refuseWritingInput(target);
  std::error_code ec;
  const stdfs::file_status status = stdfs::status(target, ec);
  if (stdfs::is_fifo(status) || stdfs::is_character_file(status)) {
    if (const int failure = writeThrough(target, static_cast<const char*>(bytes), size))
      throw Error("cannot write " + target.string() + ": " + std::strerror(failure) +
                      (failure == ENXIO ? " (a FIFO no process reads)" : ""),
                  {"write", {}, target.string()});
    return;
  }
  if (stdfs::exists(status) && !stdfs::is_regular_file(status))
    throw UsageError(target.string() +
                         " is a folder, a socket or a block device, not a file: "
                         "refusing to replace it",
                     {"write", {}, target.string()});
  const stdfs::path tmp = temporaryPathFor(target);
  const RemovedOnHardStop removedOnHardStop(tmp.string());
  int failure = writeWholeFile(tmp, static_cast<const char*>(bytes), size);
  struct stat written {};
  if (failure == 0 && ::stat(tmp.c_str(), &written) != 0) failure = errno;
  if (failure == 0 && static_cast<size_t>(written.st_size) != size) failure = EIO;
  if (failure != 0) {
    std::error_code ec;
    stdfs::remove(tmp, ec);
    throw Error("cannot write " + target.string() + ": " + std::strerror(failure) + " (" +
                    std::to_string(size) + " bytes)",
                {"write", {}, target.string()});
  }
  commitTemporary(tmp, target);
}

bool isStaleTemporary(const stdfs::path& path) {
  const std::string name = path.filename().string();
  const std::string marker = ".pluvia-tmp-";
  const size_t at = name.find(marker);
  if (at == std::string::npos) return false;
  const size_t digits = at + marker.size();
  const size_t end = name.find('-', digits);
  const std::string pid = name.substr(digits, end == std::string::npos ? end : end - digits);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos)
    return false;
  // ESRCH: no such process. EPERM means it runs (as another user): keep its files.
  if (::kill(static_cast<pid_t>(std::stol(pid)), 0) == 0 || errno != ESRCH) return false;
  // A plate frame may be named like a temporary (r.0001.pluvia-tmp-999999-0.png): kept.
  return protectedInputAt(path).empty();
}

int removeStaleTemporaries(const stdfs::path& folder, const std::string& namePrefix) {
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : stdfs::directory_iterator(folder.empty() ? "." : folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(namePrefix, 0) != 0 || !isStaleTemporary(entry.path())) continue;
    std::error_code removeError;
    removed += stdfs::remove(entry.path(), removeError) ? 1 : 0;
  }
  return removed;
}

void ensureParentFolder(const stdfs::path& file, MakeFolders make) {
  stdfs::path folder = file.parent_path();
  if (folder.empty()) return;
  std::error_code ec;
  if (make == MakeFolders::LastLevel && !stdfs::exists(folder, ec)) {
    const stdfs::path above = stdfs::absolute(folder, ec).parent_path();
    if (!stdfs::is_directory(above, ec))
      throw Error("the output folder " + folder.string() +
                      " does not exist, nor the folder above it (" + above.string() +
                      "): give --mkdir to make them",
                  {"write", {}, folder.string()});
  }
  stdfs::create_directories(folder, ec);
  if (ec)
    throw Error("cannot create output folder " + folder.string() + ": " + ec.message(),
                {"write", {}, folder.string()});
  if (access(folder.c_str(), W_OK) != 0) {
    throw Error("output folder " + folder.string() + " is not writable",
                {"write", {}, folder.string()});
  }
}

stdfs::path canonicalSpelling(const stdfs::path& path) {
  std::error_code ec;
  const stdfs::path canonical = stdfs::weakly_canonical(stdfs::absolute(path, ec), ec);
  return ec ? path : canonical;
}

bool samePath(const stdfs::path& a, const stdfs::path& b) {
  std::error_code ec;
  if (stdfs::exists(a, ec) && stdfs::exists(b, ec)) return stdfs::equivalent(a, b, ec);
  return stdfs::weakly_canonical(a, ec) == stdfs::weakly_canonical(b, ec);
}

std::string readTextFile(const stdfs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open " + path.string(), {{}, {}, path.string()});
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void requireRegularFile(const stdfs::path& path, const std::string& what) {
  std::error_code ec;
  const stdfs::file_status status = stdfs::status(path, ec);
  if (!stdfs::exists(status) || stdfs::is_regular_file(status)) return;
  const char* kind = stdfs::is_fifo(status)        ? "a FIFO"
                     : stdfs::is_directory(status) ? "a folder"
                     : stdfs::is_socket(status)    ? "a socket"
                                                   : "a device";
  throw Error(what + " " + path.string() + " is " + kind + ", not a file: refusing to read it",
              {"read", {}, path.string()});
}

std::string readInputText(const stdfs::path& path, const std::string& what) {
  requireRegularFile(path, what);
  protectInputs({path.string()});
  return readTextFile(path);
}

void writeTextFile(const stdfs::path& path, const std::string& text) {
  ensureParentFolder(path, MakeFolders::All);
  writeFileAtomically(path, text.data(), text.size());
}

}  // namespace pluvia::fs
