#include "util/log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>
#include <set>

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
// Whether `text` starts as every line of a pluvia log does: "YYYY-MM-DD HH:MM:SS pluvia: ".
bool startsAsLogLine(const char* text, size_t size) {
  static constexpr char kShape[] = "0000-00-00 00:00:00 pluvia: ";
  const size_t length = sizeof kShape - 1;
  if (size < length) return false;
  for (size_t i = 0; i < length; ++i) {
    const bool digit = kShape[i] == '0';
    if (digit ? !std::isdigit(static_cast<unsigned char>(text[i])) : text[i] != kShape[i])
      return false;
  }
  return true;
}

// The log is appended to: an existing file that is not a pluvia log (an image, a colour
// config, a LUT, a COLMAP model, any text of the user's) would be damaged by it, whether or not
// the run has read it yet (`--log plate.0002.png`, `--log config.ocio`).
void refuseFileNotALog(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return;  // new, a device, a pipe
  if (info.st_size == 0) return;
  std::FILE* existing = std::fopen(path.c_str(), "rb");
  if (!existing) return;
  char head[64];
  const size_t n = std::fread(head, 1, sizeof head, existing);
  std::fclose(existing);
  if (!startsAsLogLine(head, n))
    throw UsageError("--log " + path +
                         " is not a pluvia log (its first line is no log line): refusing to "
                         "append to it; name a new file",
                     {"write", {}, path});
}

const bool gTerminal = isatty(fileno(stderr)) != 0;

// Every line of the file is stamped, progress lines too (refuseFileNotALog knows a log by it).
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
// must not drive the terminal (util/printable.h). -q quiets the terminal, never the log file:
// it gets every message at `level` up to Info, and debug messages with -v.
void emit(Level level, const char* tag, const std::string& message) {
  const bool terminal = gLevel >= level;
  if (!terminal && level > Level::Info) return;
  const std::string shown = printable(message, /*keepLines=*/true);
  std::lock_guard lock(gMutex);
  if (terminal) {
    std::fprintf(stderr, "pluvia: %s%s\n", tag, shown.c_str());
    std::fflush(stderr);
  }
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
  fs::claimOutput(path, "--log");
  refuseFileNotALog(path);
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
  // A warning said again word for word (a movie opened by several readers, a setting every
  // chunk of frames meets) is said once: the first says all it has to.
  {
    static std::set<std::string> said;
    std::lock_guard lock(gMutex);
    if (!said.insert(m).second) return;
  }
  emit(Level::Warning, "warning: ", m);
}
void info(const std::string& m) {
  emit(Level::Info, "", m);
}
void debug(const std::string& m) {
  emit(Level::Debug, "debug: ", m);
}
void error(const std::string& m) {
  emit(Level::Quiet, "error: ", m);
}

void progress(const std::string& line, const std::string& terminalText, bool lastStep) {
  std::lock_guard lock(gMutex);
  if (gLevel >= Level::Info) {
    if (gTerminal) {
      std::fprintf(stderr, "\r%s%s", terminalText.c_str(), lastStep ? "\n" : "");
    } else if (!line.empty()) {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
  }
  if (!line.empty()) toFile("", line);
}

}  // namespace pluvia::log
