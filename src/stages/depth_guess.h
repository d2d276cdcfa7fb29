#pragma once
// The depth stage's default source ("auto"): a guess that is safe on any plate when nothing is
// known about the scene. Three parts, from the plate and the preset's camera:
//  - sky (+infinity): the sky found in the clip's still (stages/clip_still.h);
//  - the ground plane y = 0 under the camera, only where the camera says there is one
//    (camera.height_m > 0) and nearer than the backdrop;
//  - everything else at depth.backdrop_m: a finite backdrop, so fog and rain treat an unknown
//    wall or tree as something at a distance, never as sky at infinity.
// It is a guess: `pluvia plan` says so, and how to give a better depth.
#include <cstdint>
#include <vector>

#include "geometry/camera.h"

namespace pluvia {

struct DepthGuess {
  std::vector<float> depthMeters;  // width * height z-depths, +inf for sky
  double skyFraction = 0.0;        // share of the pixels taken for sky
  double groundFraction = 0.0;     // share on the ground plane
};

// The guess seen by `camera` (the plate's size), with `sky` (width * height, 1 where sky).
DepthGuess guessDepth(const std::vector<uint8_t>& sky, const Camera& camera, double backdropMeters);

}  // namespace pluvia
