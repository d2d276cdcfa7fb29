#pragma once
// The per-clip analysis a render reads from the cache (`--cache DIR`): which entries its plan
// needs, computing each one once (pipeline/cache_lock.h), and refusing to compute them where
// they must already be there (`pluvia render --require-cache`, farm chunks after `pluvia
// prepare`).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/cache.h"
#include "pipeline/cache_lock.h"
#include "pipeline/planner.h"

namespace pluvia {

struct AnalysisEntry {
  std::string stage;
  std::string key;
  std::filesystem::path path;  // the entry's file in the cache
  bool cached = false;         // in the cache when listed
};

// The entries of the stages `plan` keeps (runs or reads from the cache) whose parameters cache
// something (StageInfo::cacheKey not empty), in pipeline order.
std::vector<AnalysisEntry> clipAnalysisEntries(const Plan& plan, const Preset& preset,
                                               const ClipInfo& clip,
                                               const std::vector<StageInfo>& stages,
                                               const ArtifactCache& cache);

// Throws pluvia::Error naming every entry of `entries` not in the cache, and how to fill it.
void requireCachedAnalysis(const std::vector<AnalysisEntry>& entries, const std::string& input,
                           const std::string& cacheDir);

// True when `info` caches something with these parameters and `cache` lacks it.
bool cacheEntryMissing(const ArtifactCache* cache, const StageInfo& info, const Preset& preset,
                       const ClipInfo& clip);

// The lock of `info`'s cache entry when it is missing from `cache`, held while the stage
// prepares: it computes and stores the entry, or reads it when another process stored it while
// this one waited for the lock. nullopt when there is no cache, the stage caches nothing with
// these parameters, or the entry is there.
std::optional<CacheEntryLock> lockMissingEntry(const ArtifactCache* cache, const StageInfo& info,
                                               const Preset& preset, const ClipInfo& clip);

}  // namespace pluvia
