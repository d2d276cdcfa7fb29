#pragma once
// `pluvia prepare`: the per-clip analysis a render of this clip and preset needs (lighting,
// COLMAP tracking, strokes cut from the footage), computed once into the cache before the
// render's chunks start, so that they only read it.
#include <vector>

#include "pipeline/clip_analysis.h"
#include "pipeline/render_job.h"

namespace pluvia {

struct PrepareSummary {
  // Every entry the render needs, in pipeline order; `cached`: it was there before this run.
  std::vector<AnalysisEntry> entries;
};

// Fills request.cacheDir (required; request.output is unused and may be empty; the frame range
// is ignored: the analysis is of the whole clip) for request.input at request.proxyScale.
// Another process computing the same entry is waited for. Throws pluvia::Error when a stage
// fails or leaves its entry out of the cache.
PrepareSummary prepareJob(const RenderRequest& request, const Preset& preset,
                          const std::vector<StageInfo>& stages, StageTimes& times);

}  // namespace pluvia
