#pragma once
// A still picture of the clip for per-clip analysis (the default depth's sky, the frame
// lighting): the per-pixel median of a few frames spread over the whole clip, so that the rain
// and anything passing through are left out and every chunk of a farm render sees the same one.
#include <cstdint>
#include <vector>

#include "pipeline/stage.h"

namespace pluvia {

// The median of up to `maxFrames` frames spread evenly over `frames` (the first included), read
// in the working space. With fewer than 3 frames, the first.
Image medianOfFrames(ClipContext& clip, const std::vector<int64_t>& frames, int maxFrames);

}  // namespace pluvia
