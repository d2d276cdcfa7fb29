#pragma once
// The frame loop of a render: a reader thread (decode + colour in) at most a few frames ahead,
// the stages on the calling thread (the one that owns the GL context), and writer threads that
// encode (one for a movie, which takes its frames in order).
#include <cstdint>
#include <vector>

#include "pipeline/render_job.h"
#include "util/timer.h"

namespace pluvia {

// Renders `frames` (in increasing order) of a session whose stages are prepared into
// request.output, with request.threads writers for a sequence. Returns the number of frames
// written. On any failure every thread stops after its frame in flight and the first error is
// thrown (named by stage, frame and file); frames already written stay valid.
int renderFrames(RenderSession& session, const RenderRequest& request,
                 const std::vector<int64_t>& frames, StageTimes& times);

}  // namespace pluvia
