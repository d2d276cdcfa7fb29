#pragma once
// A render job: a clip in, rained frames out. Reading (decode + colour in) runs on its own
// thread, the stages on the render thread that owns the GL context, and encoding on a pool of
// writer threads (one for movies, which need frames in order), so I/O overlaps the work.
// Frames are independent of thread count and chunking: every per-frame result depends only on
// the preset, the seed and the frame number.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/planner.h"
#include "util/timer.h"

namespace pluvia {

struct RenderRequest {
  std::string input;
  std::string output;
  std::optional<int64_t> firstFrame;  // inclusive, clip frame numbers
  std::optional<int64_t> lastFrame;
  int threads = 2;       // writer threads for sequences
  std::string cacheDir;  // per-clip analysis cache; empty: none
  bool skipExisting = false;
  std::vector<std::string> aovs;  // "rain", "matte", "depth"
  std::string commandLine;        // recorded in the log
  bool progress = true;
};

struct RenderSummary {
  int framesWritten = 0;
  int framesSkipped = 0;  // --skip-existing: whole frames of this preset, kept
  int framesRedone = 0;   // --skip-existing: broken or other-preset frames, rendered again
  Plan plan;
};

// Opens the input and plans the job for it, without rendering.
Plan planJob(const std::string& input, const Preset& preset, const std::string& cacheDir,
             const std::vector<StageInfo>& stages, ClipInfo* clipOut = nullptr);

// Renders. Throws pluvia::Error (naming stage, frame and file) on any failure; frames already
// written stay valid, no partial frame is left behind, and no input file is ever written.
// `stages` lists every stage in pipeline order (stages/registry.h: allStages()).
RenderSummary renderJob(const RenderRequest& request, const Preset& preset,
                        const std::vector<StageInfo>& stages, StageTimes& times);

}  // namespace pluvia
