#include "pipeline/planner.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "pipeline/cache.h"

namespace pluvia {

bool Plan::runs(const std::string& stage) const {
  for (const auto& e : entries)
    if (e.stage == stage) return e.runs;
  return false;
}

bool Plan::available(const std::string& stage) const {
  for (const auto& e : entries)
    if (e.stage == stage) return e.runs || e.cached;
  return false;
}

std::string Plan::text() const {
  std::string out;
  for (const auto& e : entries) {
    const char* state = e.runs ? "run " : (e.cached ? "cached" : "skip");
    out += fmt::format("  {:<7} {:<12} {}\n", state, e.stage, e.reason);
  }
  return out;
}

Plan makePlan(const Preset& preset, const ClipInfo& clip, const ArtifactCache* cache,
              const std::string& framesKey, const std::vector<StageInfo>& stages) {
  std::vector<PlanEntry> entries(stages.size());
  // Walk backwards from the writer, which reads the image.
  std::set<std::string> needed{"image"};
  for (size_t k = stages.size(); k-- > 0;) {
    const StageInfo& info = stages[k];
    PlanEntry& entry = entries[k];
    entry.stage = info.spec.name;
    const std::string enabledKey = info.spec.name + ".enabled";
    if (preset.has(enabledKey) && !preset.boolean(enabledKey)) {
      entry.reason = fmt::format("disabled ({} = false)", enabledKey);
      continue;
    }
    if (std::string why = info.noOpReason ? info.noOpReason(preset) : ""; !why.empty()) {
      entry.reason = "no-op: " + why;
      continue;
    }
    std::vector<std::string> readers;
    for (const auto& output : info.spec.outputs) {
      if (needed.count(output)) readers.push_back(output);
    }
    if (readers.empty()) {
      entry.reason =
          fmt::format("nothing reads its output ({})", fmt::join(info.spec.outputs, ", "));
      continue;
    }
    const std::string key = info.cacheKey ? info.cacheKey(preset, clip) : "";
    const bool inCache = cache && !key.empty() && cache->contains(info.spec.name, key);
    if (info.perClip && inCache) {
      entry.cached = true;
      entry.reason =
          fmt::format("result in cache ({})", cache->pathFor(info.spec.name, key).string());
      continue;
    }
    entry.runs = true;
    entry.reason = fmt::format("writes {}", fmt::join(readers, ", "));
    if (std::string note = info.note ? info.note(preset) : ""; !note.empty())
      entry.reason += "; " + note;
    if (cache && info.cachedWork) {
      if (std::string cached = info.cachedWork(preset, clip, framesKey, *cache); !cached.empty())
        entry.reason += "; " + cached;
    }
    // A per-frame stage with per-clip analysis (depth from COLMAP): say whether that is done.
    if (!info.perClip && !key.empty()) {
      entry.reason += inCache ? fmt::format("; per-clip analysis cached ({})",
                                            cache->pathFor(info.spec.name, key).string())
                      : cache ? std::string("; per-clip analysis needed (not in the cache)")
                              : std::string("; per-clip analysis needed (no --cache)");
    }
    for (const auto& input : info.reads ? info.reads(preset) : info.spec.inputs)
      needed.insert(input);
  }
  // Cached per-clip results still feed their readers: keep the reads of cached stages out,
  // since a cached stage reads nothing.
  entries.push_back({"write", true, false, "writes the frames"});
  return Plan{entries};
}

}  // namespace pluvia
