#include "util/log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>

#include "util/error.h"
#include "util/input_guard.h"
#include "util/printable.h"

namespace pluvia::log {
namespace {
std::atomic<Level> gLevel{Level::Info};
std::mutex gMutex;
std::FILE* gFile = nullptr;  // --log FILE, guarded by gMutex
std::string gFilePath;
bool gFileFailed = false;

// A write to the log file failed (a full disk, /dev/full): say so once on stderr and stop
// writing to it; the command's exit code says it too (fileFailed()).
void fileWriteFailed() {
  const int code = errno;
  std::fclose(gFile);
  gFile = nullptr;
  gFileFailed = true;
  std::fprintf(stderr, "pluvia: warning: the log file %s stops here: %s\n", gFilePath.c_str(),
               std::strerror(code));
  std::fflush(stderr);
}
// The log is appended to: a file holding NUL bytes (an image, a movie, an archive) is no text
// log, and appending would damage it (`--log plate.0002.png`).
void refuseBinaryFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return;  // new, a device, a pipe
  std::FILE* existing = std::fopen(path.c_str(), "rb");
  if (!existing) return;
  char head[65536];
  const size_t n = std::fread(head, 1, sizeof head, existing);
  std::fclose(existing);
  if (std::memchr(head, '\0', n))
    throw UsageError(
        "--log " + path + " is not a text log (it holds binary data): refusing to append to it",
        {"write", {}, path});
}

const bool gTerminal = isatty(fileno(stderr)) != 0;

void toFile(const char* tag, const std::string& message) {
  if (!gFile) return;
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", &local);
  if (std::fprintf(gFile, "%s pluvia: %s%s\n", stamp, tag, message.c_str()) < 0 ||
      std::fflush(gFile) != 0)
    fileWriteFailed();
}

// Control characters from names, tags and preset values are shown escaped: an escape sequence
// must not drive the terminal (util/printable.h).
void emit(const char* tag, const std::string& message) {
  const std::string shown = printable(message, /*keepLines=*/true);
  std::lock_guard lock(gMutex);
  std::fprintf(stderr, "pluvia: %s%s\n", tag, shown.c_str());
  std::fflush(stderr);
  toFile(tag, shown);
}
}  // namespace

void setLevel(Level level) {
  gLevel = level;
}
Level level() {
  return gLevel;
}

void setFile(const std::string& path) {
  std::lock_guard lock(gMutex);
  if (gFile) std::fclose(gFile);
  gFile = nullptr;
  if (path.empty()) return;
  fs::refuseWritingInput(path);
  refuseBinaryFile(path);
  gFilePath = path;
  gFileFailed = false;
  gFile = std::fopen(path.c_str(), "a");
  if (!gFile)
    throw Error("cannot open the log file " + path + ": " + std::strerror(errno),
                {"write", {}, path});
}

std::string filePath() {
  std::lock_guard lock(gMutex);
  return gFile ? gFilePath : std::string();
}

bool fileFailed() {
  std::lock_guard lock(gMutex);
  return gFileFailed;
}

void warning(const std::string& m) {
  if (gLevel >= Level::Warning) emit("warning: ", m);
}
void info(const std::string& m) {
  if (gLevel >= Level::Info) emit("", m);
}
void debug(const std::string& m) {
  if (gLevel >= Level::Debug) emit("debug: ", m);
}
void error(const std::string& m) {
  emit("error: ", m);
}

void progress(const std::string& line, const std::string& terminalText, bool lastStep) {
  if (gLevel < Level::Info) return;
  std::lock_guard lock(gMutex);
  if (gTerminal) {
    std::fprintf(stderr, "\r%s%s", terminalText.c_str(), lastStep ? "\n" : "");
  } else if (!line.empty()) {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
  if (gFile && !line.empty() &&
      (std::fprintf(gFile, "%s\n", line.c_str()) < 0 || std::fflush(gFile) != 0))
    fileWriteFailed();
}

}  // namespace pluvia::log
