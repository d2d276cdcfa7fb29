#pragma once
// One process computes each per-clip cache entry, however many renders of the clip need it at
// once (farm chunks started together, or before `pluvia prepare` is done): the first to find
// the entry missing locks it (util/file_lock.h) and computes it; the others wait for the lock
// and then read what it stored. Over a farm's shared disk the lock holds between hosts.
#include <string>

#include "pipeline/cache.h"
#include "util/file_lock.h"

namespace pluvia {

// The lock file beside an entry: "DIR/lighting-KEY.json.pluvia-lock".
std::string cacheEntryLockPath(const ArtifactCache& cache, const std::string& stage,
                               const std::string& key);

class CacheEntryLock {
 public:
  // Blocks until this process holds the entry's lock, saying once in the log which process
  // holds it meanwhile. Throws Interrupted on SIGINT or SIGTERM while it waits.
  CacheEntryLock(const ArtifactCache& cache, const std::string& stage, const std::string& key);
  // True when another process held the entry first (and has likely stored it since).
  bool waited() const { return waited_; }

 private:
  bool waited_ = false;
  FileRangeLock lock_;
};

}  // namespace pluvia
