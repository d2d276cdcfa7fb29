#pragma once
// A quick test, before COLMAP runs, of whether the camera moved enough to see depth.
//
// A camera that only rotates (a pan or tilt from a tripod), or that barely moves relative to the
// scene depth, maps one frame onto another by a homography: no parallax, so structure from motion
// cannot give depth (and COLMAP's mapper then spends minutes failing). Pairs of frames far apart
// in the clip are matched (SIFT, ratio test), a homography and a fundamental matrix are fitted
// (RANSAC), and the fundamental inliers that the homography misses by more than
// parallaxThresholdPx count as parallax. If every pair with enough matches has fewer than
// minParallaxFraction of such matches, the clip is a pan.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia {

struct ParallaxCheckSettings {
  int maxImageSizePx = 640;           // frames are matched at this longest side
  double parallaxThresholdPx = 2.0;   // homography residual that counts as parallax, at that size
  double minParallaxFraction = 0.08;  // of the fundamental-matrix inliers
  int minMatches = 40;                // pairs with fewer matches say nothing
};

enum class ParallaxVerdict { Parallax, NoParallax, Unknown };

struct ParallaxCheck {
  ParallaxVerdict verdict = ParallaxVerdict::Unknown;
  double parallaxFraction = 0.0;  // the largest over the pairs that had enough matches
  int pairsJudged = 0;
  std::string message;  // for a NoParallax verdict: what was measured
};

// `frames`: the clip's frames in order (8-bit or float 0..1; grey, RGB or RGBA), at least 2.
ParallaxCheck checkParallax(const std::vector<cv::Mat>& frames,
                            const ParallaxCheckSettings& settings = {});

}  // namespace pluvia
