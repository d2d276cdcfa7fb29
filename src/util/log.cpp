#include "util/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace pluvia::log {
namespace {
std::atomic<Level> gLevel{Level::Info};
std::mutex gMutex;

void emit(const char* tag, const std::string& message) {
  std::lock_guard lock(gMutex);
  std::fprintf(stderr, "pluvia: %s%s\n", tag, message.c_str());
  std::fflush(stderr);
}
}  // namespace

void setLevel(Level level) { gLevel = level; }
Level level() { return gLevel; }
void warning(const std::string& m) {
  if (gLevel >= Level::Warning) emit("warning: ", m);
}
void info(const std::string& m) {
  if (gLevel >= Level::Info) emit("", m);
}
void debug(const std::string& m) {
  if (gLevel >= Level::Debug) emit("debug: ", m);
}
void error(const std::string& m) { emit("error: ", m); }

}  // namespace pluvia::log
