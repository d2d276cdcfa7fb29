#pragma once
// A clip of known answer for registration with parallax: a camera moving sideways past two
// depths. The far layer is a photograph, the near one pillars cut from the same photograph
// turned upside down and darkened (another texture), crossing the frame faster than the far
// layer does, so no single homography lines the frames up. Shifts are whole pixels, so every
// frame is as sharp as the photograph and the clean frames are exact.
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::lab {

struct ParallaxClipSettings {
  int frames = 9;
  int farShiftPxPerFrame = 2;   // the photograph's motion, right to left
  int nearShiftPxPerFrame = 7;  // the pillars'
  int pillarWidthPx = 28;
  int pillarSpacingPx = 90;  // from one pillar's left edge to the next one's
};

// The clean frames (CV_32FC3, `size`, cut from the middle of `photo`; the middle frame unshifted).
// Throws pluvia::Error when the photo is not CV_32FC3 or is smaller than `size`.
std::vector<cv::Mat> makeParallaxClip(const cv::Mat& photo, cv::Size size,
                                      const ParallaxClipSettings& settings = {});

}  // namespace pluvia::lab
