#pragma once
// Checks of a metric reconstruction's gravity and scale against cues independent of the ones that
// set them: a camera-height scale assumes one height, so the spread of the cameras' heights above
// the fitted ground tests it; façade lines show buildings, which stand taller than the camera; a
// clip's frame rate turns the camera's travel into a speed. A failed check is a warning naming
// its numbers (SfmReconstruction::warnings), and nothing is changed: the cues can be wrong too.
#include "sfm/sfm_poses.h"

namespace pluvia::sfm {

// Fills structureHeightMeters and medianCameraSpeedMetersPerSecond of `sfm` (metric, with its
// keyframes' heights when it stands on a ground) and appends a warning for each cue that
// disagrees: the ground's tilt from the façades' vertical, the camera heights' spread, the
// structures' height, the camera's speed.
void checkScaleCues(SfmReconstruction& sfm, const SfmOptions& options);

// How bent a model that built looks, by the two cues a bent bundle adjustment fails (COLMAP's
// two-thread mapper bent a street in 2 of 10 runs: the ground tilted 10 deg from the façades):
// the larger of the ground's tilt from the façades' vertical over maxGroundTiltFromVerticalDeg
// and the camera heights' spread over maxCameraHeightSpread. Above 1 the model is bent; a cue
// that was not measured counts 0. `reason`, when given and the model is bent, gets why.
double bentness(const SfmReconstruction& sfm, const SfmOptions& options,
                std::string* reason = nullptr);

}  // namespace pluvia::sfm
