#pragma once
// The planner: which stages this shot needs. A stage is left out when it is disabled, when its
// parameters make it a no-op (OCIO's isNoOp), when nothing downstream reads what it writes
// (dead-code elimination over declared outputs), or, for per-clip analysis, when its result is
// already in the cache.
#include <string>
#include <vector>

#include "pipeline/stage.h"

namespace pluvia {

struct PlanEntry {
  std::string stage;
  bool runs = false;
  bool cached = false;  // per-clip result comes from the cache (runs is false)
  std::string reason;   // why it runs or why it is left out
};

// An artifact the planned stages pass on (pipeline/stage.h): what makes it (stages that run or
// come from the cache, and what makes it outside the stages) and the stages that run and read it.
struct PlanArtifact {
  std::string name;
  std::vector<std::string> madeBy, readBy;
};

struct Plan {
  std::vector<PlanEntry> entries;       // pipeline order, "write" last
  std::vector<PlanArtifact> artifacts;  // in order of first use, "image" left out
  bool runs(const std::string& stage) const;
  bool available(const std::string& stage) const;  // runs or cached
  // Human-readable: one line per stage, then one per artifact.
  std::string text() const;
  // One line for a render's log: the stages that run, those cached and those left out with why
  // ("runs lighting, rain, write; cached depth; leaves out fog [no-op: density is 0]").
  std::string summary() const;
};

// `framesKey`: the key the clip's per-clip work is stored under in `cache` (render_job.h's
// workingFramesKey, made once by the caller: it reads samples of the plate's files); "" without a
// cache.
Plan makePlan(const Preset& preset, const ClipInfo& clip, const ArtifactCache* cache,
              const std::string& framesKey, const std::vector<StageInfo>& stages);

}  // namespace pluvia
