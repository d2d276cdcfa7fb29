#pragma once
// The rain layer on the ground (`pluvia report realism`'s ground row): what lands, not what
// falls. Splash crowns, their droplets and ripple rings are small roundish blobs in the layer
// dI = luma(frame) - luma(plate) where it shows the ground; falling streaks are long. Over the
// frame's bottom third (a report cannot know where a clip's ground is: the bottom third is where
// a camera that looks at ground sees it, and holds no sky on the clips measured so far), each
// frame's |dI| > kGroundBlobCodes is cut into 8-connected blobs; a blob counts when it covers
// 2 to 400 px (at the report's 640 px width: a crown or a ring, not a patch of the plate) and
// its bounding box is at most kRoundAspect times longer than wide (not a streak). Measured:
//  - blobs per Mpx of the region, per frame, mean;
//  - their area, px, median;
//  - their lifetime in frames: a blob continues one of the previous frame's when its centroid
//    lies within kContinuePx of it; with a share f of blobs continuing, a blob lives 1 / (1 - f)
//    frames on average;
//  - their |dI|, codes, p90 over the blobs' pixels.
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::lab {

inline constexpr double kGroundBlobCodes = 10.0;
inline constexpr double kRoundAspect = 2.0;
inline constexpr double kContinuePx = 2.0;
inline constexpr double kGroundTopFraction = 2.0 / 3.0;  // the region starts this far down

struct GroundStats {
  double blobsPerMpx = 0.0;
  double areaP50Px = 0.0;
  double lifetimeFrames = 0.0;
  double deltaP90 = 0.0;
  int frames = 0;
};

// The statistics of a clip's layers (codes, one per frame, in frame order).
GroundStats measureGroundLayers(const std::vector<cv::Mat1f>& layers);

}  // namespace pluvia::lab
