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
  if (artifacts.empty()) return out;
  out += "  artifacts (made by -> read by; the image passes through every stage that runs):\n";
  for (const auto& a : artifacts)
    out += fmt::format("    {:<18} {} -> {}\n", a.name,
                       a.madeBy.empty() ? "nothing" : fmt::format("{}", fmt::join(a.madeBy, ", ")),
                       a.readBy.empty() ? "-" : fmt::format("{}", fmt::join(a.readBy, ", ")));
  return out;
}

std::string Plan::summary() const {
  std::vector<std::string> running, cached, leftOut;
  for (const auto& e : entries) {
    if (e.runs)
      running.push_back(e.stage);
    else if (e.cached)
      cached.push_back(e.stage);
    else
      leftOut.push_back(fmt::format("{} [{}]", e.stage, e.reason));
  }
  std::string out = fmt::format("runs {}", fmt::join(running, ", "));
  if (!cached.empty()) out += fmt::format("; cached {}", fmt::join(cached, ", "));
  if (!leftOut.empty()) out += fmt::format("; leaves out {}", fmt::join(leftOut, ", "));
  return out;
}

namespace {

// Who makes and who reads each artifact among the stages the plan keeps: a cached stage makes
// its outputs and reads nothing.
std::vector<PlanArtifact> planArtifacts(const Preset& preset, const std::vector<PlanEntry>& entries,
                                        const std::vector<StageInfo>& stages) {
  std::vector<PlanArtifact> artifacts;
  auto artifact = [&](const std::string& name) -> PlanArtifact& {
    for (auto& a : artifacts)
      if (a.name == name) return a;
    artifacts.push_back({name, {}, {}});
    const auto outside = artifactsMadeOutsideStages().find(name);
    if (outside != artifactsMadeOutsideStages().end())
      artifacts.back().madeBy.push_back(outside->second);
    return artifacts.back();
  };
  for (size_t k = 0; k < stages.size(); ++k) {
    const StageInfo& info = stages[k];
    if (!entries[k].runs && !entries[k].cached) continue;
    if (entries[k].runs)
      for (const auto& input : info.reads ? info.reads(preset) : info.spec.inputs)
        if (input != "image") artifact(input).readBy.push_back(info.spec.name);
    for (const auto& output : info.writes ? info.writes(preset) : info.spec.outputs)
      if (output != "image") artifact(output).madeBy.push_back(info.spec.name);
  }
  return artifacts;
}

}  // namespace

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
    const std::vector<std::string> writes = info.writes ? info.writes(preset) : info.spec.outputs;
    for (const auto& output : writes) {
      if (needed.count(output)) readers.push_back(output);
    }
    if (readers.empty()) {
      entry.reason = fmt::format("nothing reads its output ({})", fmt::join(writes, ", "));
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
  std::vector<PlanArtifact> artifacts = planArtifacts(preset, entries, stages);
  entries.push_back({"write", true, false, "writes the frames"});
  return Plan{entries, std::move(artifacts)};
}

}  // namespace pluvia
