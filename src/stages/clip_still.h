#pragma once
// A still picture of the clip for per-clip analysis (the default depth's sky, the lighting from
// the plate): the per-pixel median of a few frames spread over the whole clip, so that the rain
// and anything passing through are left out and every chunk of a farm render sees the same one,
// and the sky found in it. Each is made once per clip and kept in the ClipContext.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "pipeline/stage.h"

namespace pluvia {

// The median of up to `maxFrames` frames spread evenly over `frames` (the first included), read
// in the working space. With fewer than 3 frames, the first.
Image medianOfFrames(ClipContext& clip, const std::vector<int64_t>& frames, int maxFrames);

// The median of up to kStillFrames frames of the whole clip (clip.still, made on first use).
const Image& clipStill(ClipContext& clip);

// The sky in the still (clip.stillSky, made on first use): bright, untextured regions touching
// the top of the frame and above the horizon of `camera` (the camera of the clip's first frame),
// as geometry/sky_mask.h finds it. 1 where sky.
const std::vector<uint8_t>& clipSky(ClipContext& clip, const Camera& camera);

// The sky in one image (the still, or a frame of a moving camera's clip), as clipSky finds it.
std::vector<uint8_t> skyInImage(const Image& image, const Camera& camera);

// The same at the size the sky is found at (its longest side 480 px): the mask (CV_8U, 255 where
// sky) and the image's grey (CV_32F, linear), and the mask brought to width x height (1 where sky).
struct SmallSky {
  cv::Mat sky, grey;
};
SmallSky smallSkyOf(const Image& image, const Camera& camera);
std::vector<uint8_t> fullSizeSky(const cv::Mat& small, int width, int height);

// How far the still is from standing for the clip's frames: the largest share, over the frames
// the still is the median of, of a frame's pixels that show something else than the still
// (kMovedCodes off, rain filtered out). Near 0 on a locked-off camera with a few people passing;
// a large part of the frame when the camera moves, and then the still's sky is no frame's.
double stillMismatch(ClipContext& clip);

// For the plan (StageInfo::cachedWork): "the still from the cache" when `cache` holds it for the
// clip's frames (`framesKey`: render_job.h's workingFramesKey), else "".
std::string cachedStillNote(const std::string& framesKey, const ArtifactCache& cache);

}  // namespace pluvia
