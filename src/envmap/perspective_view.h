#pragma once
// Perspective frames cut from an equirect environment, as a camera would record them: for
// measuring the panorama against the environment it came from (pluvia report envmap), and for
// tests with known camera poses.
#include <opencv2/core.hpp>

#include "envmap/panorama.h"
#include "image/equirect.h"

namespace pluvia::envmap {

struct RecordedFrame {
  PanoramaFrame frame;  // linear RGB after the camera's 8-bit clip (and mask of clipped pixels)
  cv::Mat displayRgb8;  // CV_8UC3 R G B, sRGB-encoded, what the camera stored
};

// The view of `environment` from a pinhole camera (pose, `width` x `height`), exposed by
// `exposure` (radiance times exposure = 1 is white), stored as 8-bit sRGB with clipping.
RecordedFrame recordView(const EquirectMap& environment, const CameraPose& pose, int width,
                         int height, double exposure);

// A pose looking at yaw (degrees, positive to the right of -Z) and pitch (positive up), with a
// focal length for the given horizontal field of view and image width.
CameraPose panPose(double yawDeg, double pitchDeg, double horizontalFovDeg, int width);

}  // namespace pluvia::envmap
