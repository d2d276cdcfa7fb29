#include "pipeline/clip_analysis.h"

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {

std::vector<AnalysisEntry> clipAnalysisEntries(const Plan& plan, const Preset& preset,
                                               const ClipInfo& clip,
                                               const std::vector<StageInfo>& stages,
                                               const ArtifactCache& cache) {
  std::vector<AnalysisEntry> entries;
  for (const StageInfo& info : stages) {
    const std::string& stage = info.spec.name;
    if (!plan.available(stage) || !info.cacheKey) continue;
    const std::string key = info.cacheKey(preset, clip);
    if (key.empty()) continue;
    entries.push_back({stage, key, cache.pathFor(stage, key), cache.contains(stage, key)});
  }
  return entries;
}

void requireCachedAnalysis(const std::vector<AnalysisEntry>& entries, const std::string& input,
                           const std::string& cacheDir) {
  std::string missing;
  for (const AnalysisEntry& entry : entries) {
    if (entry.cached) continue;
    missing +=
        fmt::format("{}{} ({})", missing.empty() ? "" : ", ", entry.stage, entry.path.string());
  }
  if (missing.empty()) return;
  throw Error(fmt::format("--require-cache: the per-clip analysis of {} is not in {}: {}; run "
                          "`pluvia prepare` with the same input, preset, --set and --proxy "
                          "first (on a farm: is {} the same folder on every node?)",
                          input, cacheDir, missing, cacheDir),
              {"prepare", {}, cacheDir});
}

bool cacheEntryMissing(const ArtifactCache* cache, const StageInfo& info, const Preset& preset,
                       const ClipInfo& clip) {
  if (!cache || !info.cacheKey) return false;
  const std::string key = info.cacheKey(preset, clip);
  return !key.empty() && !cache->contains(info.spec.name, key);
}

std::optional<CacheEntryLock> lockMissingEntry(const ArtifactCache* cache, const StageInfo& info,
                                               const Preset& preset, const ClipInfo& clip) {
  if (!cacheEntryMissing(cache, info, preset, clip)) return std::nullopt;
  return std::make_optional<CacheEntryLock>(*cache, info.spec.name, info.cacheKey(preset, clip));
}

}  // namespace pluvia
