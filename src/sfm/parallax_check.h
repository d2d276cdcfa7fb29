#pragma once
// How much parallax a clip's frames show, measured before COLMAP runs: whether the camera moved
// enough to see depth at all, and which frames to track.
//
// A camera that only rotates (a pan or tilt from a tripod), or that barely moves relative to the
// scene depth, maps one frame onto another by a homography: no parallax, so structure from motion
// cannot give depth (and COLMAP's mapper then spends minutes failing). For a pair of frames,
// SIFT matches (ratio test) are fitted with a homography and a fundamental matrix (RANSAC); the
// share of the fundamental inliers that the homography misses by more than parallaxThresholdPx
// is the pair's parallax fraction.
#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::sfm {

struct ParallaxCheckSettings {
  int maxImageSizePx = 640;           // frames are matched at this longest side
  double parallaxThresholdPx = 2.0;   // homography residual that counts as parallax, at that size
  double minParallaxFraction = 0.08;  // below this over the whole clip: a pan
  // Consecutive tracked frames (selectKeyframes) should show at least this much: neighbouring
  // video frames a few centimetres apart triangulate at a fraction of a degree, and COLMAP's
  // mapper then starts from a pair whose points are noise (it failed on all 48 frames of the
  // synthetic walk, 5 cm apart, and tracked every 4th, where this reaches 0.16).
  double keyframeParallaxFraction = 0.15;
  int minMatches = 40;  // pairs with fewer matches say nothing
};

enum class ParallaxVerdict { Parallax, NoParallax, Unknown };

struct ParallaxCheck {
  ParallaxVerdict verdict = ParallaxVerdict::Unknown;
  double parallaxFraction = 0.0;  // the largest over the pairs that had enough matches
  int pairsJudged = 0;
  std::string message;  // for a NoParallax verdict: what was measured
};

// Features of a clip's frames, matched pair by pair on demand. `frames`: the frames in order
// (8-bit or float 0..1; grey, RGB or RGBA).
class ParallaxProbe {
 public:
  explicit ParallaxProbe(const std::vector<cv::Mat>& frames,
                         const ParallaxCheckSettings& settings = {});
  size_t size() const { return features_.size(); }
  // The pair's parallax fraction and the fundamental inliers it was measured on (0 and 0 when
  // fewer than minMatches matched).
  double parallaxFraction(size_t a, size_t b, int* inliers = nullptr) const;

 private:
  struct Features {
    std::vector<cv::KeyPoint> points;
    cv::Mat descriptors;
  };
  ParallaxCheckSettings settings_;
  std::vector<Features> features_;
};

// The first frame against frames a quarter, half and all the way through the clip: if every pair
// with enough matches shows less than minParallaxFraction, the clip is a pan.
ParallaxCheck checkParallax(const ParallaxProbe& probe, const ParallaxCheckSettings& settings = {});
ParallaxCheck checkParallax(const std::vector<cv::Mat>& frames,
                            const ParallaxCheckSettings& settings = {});

// Indices of the frames to track, the first and last included: from each tracked frame, the
// first later frame showing keyframeParallaxFraction against it, or, when matches thin out
// (fewer than half of those with the next frame, or under minMatches) before that, the frame
// before.
std::vector<size_t> selectKeyframes(const ParallaxProbe& probe,
                                    const ParallaxCheckSettings& settings = {});

}  // namespace pluvia::sfm
