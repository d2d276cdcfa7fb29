#include "pipeline/prepare_job.h"

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {

PrepareSummary prepareJob(const RenderRequest& request, const Preset& preset,
                          const std::vector<StageInfo>& stages, StageTimes& times) {
  if (request.cacheDir.empty()) throw UsageError("pluvia prepare needs --cache DIR");
  RenderRequest wholeClip = request;
  wholeClip.firstFrame.reset();
  wholeClip.lastFrame.reset();
  wholeClip.output = {};
  wholeClip.requireCache = false;
  RenderSession session(wholeClip, preset, stages, times);
  const ArtifactCache& cache = *session.cache();
  PrepareSummary summary;
  summary.entries = clipAnalysisEntries(session.plan(), preset, session.clip(), stages, cache);
  // Every stage, not only those with an entry of their own: their per-clip work goes into the
  // cache too (the still, the sky, the plate's rain, the drop's radiance maps), so that the
  // chunks after a prepare make none of it.
  session.prepareStages();
  for (const AnalysisEntry& entry : summary.entries) {
    if (!cache.contains(entry.stage, entry.key))
      throw Error(fmt::format("{}: the per-clip analysis was not stored in {}", entry.stage,
                              entry.path.string()),
                  {entry.stage, {}, entry.path.string()});
  }
  return summary;
}

}  // namespace pluvia
