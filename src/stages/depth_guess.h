#pragma once
// The depth stage's default source ("auto"): a guess that is safe on any plate when nothing is
// known about the scene. Three parts, from the plate and the preset's camera:
//  - sky (+infinity): bright, untextured regions touching the top of the frame and above the
//    camera's horizon (the same rule as the COLMAP densifier's sky, sfm/sparse_densify.h step 4),
//    found once per clip on the per-pixel median of a few frames spread over the whole clip (so
//    every chunk of a farm render finds the same sky, and the rain does not count as texture);
//  - the ground plane y = 0 under the camera, only where the camera says there is one
//    (camera.height_m > 0) and nearer than the backdrop;
//  - everything else at depth.backdrop_m: a finite backdrop, so fog and rain treat an unknown
//    wall or tree as something at a distance, never as sky at infinity.
// It is a guess: `pluvia plan` says so, and how to give a better depth.
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"

namespace pluvia {

struct DepthGuess {
  std::vector<float> depthMeters;  // width * height z-depths, +inf for sky
  double skyFraction = 0.0;        // share of the pixels taken for sky
  double groundFraction = 0.0;     // share on the ground plane
};

// The guess for `plate` (the clip's median frame) seen by `camera` (its size is the plate's).
DepthGuess guessDepth(const Image& plate, const Camera& camera, double backdropMeters);

}  // namespace pluvia
