#include "pipeline/cache_lock.h"

#include <chrono>
#include <thread>

#include <fmt/format.h>

#include "util/interrupt.h"
#include "util/log.h"

namespace pluvia {
namespace {

// How often a waiting process tries the lock again (the analysis it waits for takes seconds to
// minutes).
constexpr auto kPollInterval = std::chrono::milliseconds(200);

FileRangeLock waitForLock(const std::string& path, const std::string& stage, bool& waited) {
  LockConflict conflict;
  while (true) {
    if (auto lock = FileRangeLock::tryLock(path, 0, 0, &conflict)) return std::move(*lock);
    if (!waited) {
      log::info(
          fmt::format("{}: waiting for the process computing this clip's analysis (pid and "
                      "host: {}; lock file {})",
                      stage, conflict.holder, path));
      waited = true;
    }
    throwIfInterrupted();
    std::this_thread::sleep_for(kPollInterval);
  }
}

}  // namespace

std::string cacheEntryLockPath(const ArtifactCache& cache, const std::string& stage,
                               const std::string& key) {
  return cache.pathFor(stage, key).string() + ".pluvia-lock";
}

CacheEntryLock::CacheEntryLock(const ArtifactCache& cache, const std::string& stage,
                               const std::string& key)
    : lock_(waitForLock(cacheEntryLockPath(cache, stage, key), stage, waited_)) {}

}  // namespace pluvia
