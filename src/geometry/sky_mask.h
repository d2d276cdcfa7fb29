#pragma once
// Where a frame shows sky, found in the picture alone (no depth needed): the depth guess of a
// plate without tracking marks it, and the COLMAP densifier (sfm/sparse_densify.h, step 4) marks
// it among its samples. Conservative:
//  - candidates are bright (brightest channel at least minBrightness of the frame's near-white
//    level, and minSkyCode in display codes) and not warm (brick is not sky), untextured (the
//    incoherent gradient, the mean of |gradient| over 9x9 minus the |mean gradient|, below
//    maxGradient: a smooth sky gradient or a soft cloud edge has almost none, texture and noise
//    do), not riddled with specks (a wall), and, with a ground camera, at least minElevationDeg
//    above the horizon (nothing below it is sky);
//  - seeds are candidate regions farther than minDistanceFraction of the diagonal from every
//    depth sample, touching the top row and at least a disc of that radius in area;
//  - they grow through candidates with no strong edge of their own up to growMinDistancePx of a
//    sample and no more than the seed distance from the seeds (so the sky reaches a roof line
//    without leaking into a wall), then by the texture test's half-window through bright,
//    speckless pixels with no strong edge (the sky just above a roof line fails that test);
//  - holes inside the sky holding no sample and not reaching the frame's border (a cloud's
//    edge) are filled.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/camera.h"

namespace pluvia {

struct SkyMaskSettings {
  double minDistanceFraction = 0.03;  // of the image diagonal, from the nearest sample (seeds)
  double growMinDistancePx = 6.0;     // from the nearest sample, for the grown sky
  double maxGradient = 3.0;           // incoherent gradient, grey levels per pixel
  double minBrightness = 0.65;        // brightest channel, of the frame's 99th percentile
  // and at least this display code: the sky lights the scene, so in a frame exposed for that
  // scene it sits high in the range (overcast 180-255, blue 200 and over on every plate here);
  // a frame whose brightest pixels stay below it shows no sky (a camera looking down at a wet
  // road, whose lighter far part passed the relative test alone).
  double minSkyCode = 140.0;
  double minElevationDeg = 1.5;  // above the ground camera's horizon
  // The horizon bounds where the sky may start (its seeds' top row), not how far it reaches
  // below: where the camera is a guess (estimateSkyMask: the preset's tilt), a photo looking up
  // has clear sky under the guess's horizon, and cutting it there drew a seam across the sky.
  bool horizonBoundsSeedsOnly = false;
  // Sky regions cut apart by a wire or a branch are joined when they come within bridgePx of
  // each other (the line and the band the texture test leaves around it: about 10 px for a 1 px
  // wire at the 480 px the sky is found at) and their colours on either side of it agree within
  // bridgeCodes (display codes, each channel). The lines themselves, at most 2 lineRadiusPx wide
  // between sky on both sides, are sky too: a wire is graded as the sky around it.
  int bridgePx = 8;
  double bridgeCodes = 6.0;
  int lineRadiusPx = 3;
  double maxRedOverBlue = 1.3;  // display codes: warmer (and red over green) is no sky
  // Specks (regions of at most maxSpeckAreaPx that fail the brightness or texture test,
  // enclosed by pixels that pass, holding a pixel that fails the brightness test) over more
  // than maxSpeckDensity of the pixels within speckWindowRadiusPx make a wall, not sky: the sky
  // is clear or smoothly clouded, and a cloud's textured wisps are as bright as the sky.
  int maxSpeckAreaPx = 400;
  int speckWindowRadiusPx = 12;
  double maxSpeckDensity = 0.005;
};

// The guide's colour channels (alpha dropped), 8-bit; float input is linear light given a
// display gamma of 2.2, so edges in shadows count as much as they look.
std::vector<cv::Mat> colourChannels(const cv::Mat& guide);

// Inverse z-depth (CV_32F) of the ground plane y = 0 seen by `camera` at a frame of width x
// height (0 where the ray does not meet it within maxDistanceMeters), and the sine of each
// ray's elevation above the horizon.
void groundPlane(const Camera& camera, int width, int height, double maxDistanceMeters,
                 cv::Mat& inverseDepth, cv::Mat& sinElevation);

// 255 where `guide` (8-bit or float linear, 1, 3 or 4 channels, BGR) shows sky. `sampleMask`
// (CV_8U): the pixels that hold depth samples; `distancePx` (CV_32F): to the nearest sample;
// `sinElevation`: from groundPlane, empty without a ground camera.
cv::Mat skyMask(const cv::Mat& guide, const cv::Mat& sampleMask, const cv::Mat& distancePx,
                const cv::Mat& sinElevation, const SkyMaskSettings& settings);

// The same for a frame with no depth samples at all (the default depth's guess): every pixel
// counts as far from a sample; the horizon test uses `groundCamera` when given, for the seeds
// alone (horizonBoundsSeedsOnly: that camera's tilt is the preset's guess).
cv::Mat estimateSkyMask(const cv::Mat& guide, const std::optional<Camera>& groundCamera,
                        double groundMaxDistanceMeters = 100.0,
                        const SkyMaskSettings& settings = {});

}  // namespace pluvia
