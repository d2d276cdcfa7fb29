#pragma once
// The data the rain-extraction solver (Wang et al. Eq. 1) works on, and the rain-angle
// convention every derain file shares.
//
// Conventions:
//  - frames are CV_32FC3 in channel order R, G, B (not OpenCV's BGR), row 0 at the top, holding
//    the file's own values (display-encoded for video and 8/16-bit images, as the clip reader
//    returns them; no colour conversion), nominally 0..1. Eq. (1) is applied to these values,
//    as the paper applies it to its video's pixels: sensor and compression noise is close to
//    uniform there, which is what least squares assumes, while averaging linearised values
//    would bias dark pixels (Jensen's inequality). Rain mattes are shapes, used normalised;
//  - a matte alpha is CV_32FC1 in 0..1, one per frame;
//  - the rain angle, in degrees in (-90, 90], is the angle between the streaks and the image
//    vertical, positive when a streak's upper end lies to the right of its lower end.
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::derain {

struct FrameStack {
  std::vector<cv::Mat> frames;  // CV_32FC3 each, all the same size
  // Optional, one per frame: CV_8UC1, nonzero where the frame saw the pixel (after registration
  // some of the reference frame lies outside a warped frame). Empty: every pixel is valid.
  std::vector<cv::Mat> valid;

  cv::Size size() const { return frames.empty() ? cv::Size() : frames[0].size(); }
};

// Unit vector along a streak, from its lower end to its upper end, in image coordinates
// (x right, y down): (sin a, -cos a).
cv::Vec2d streakDirection(double angleDeg);
// Folds any angle into (-90, 90] (a streak has no sense: a and a + 180 are the same line).
double foldRainAngleDeg(double angleDeg);

}  // namespace pluvia::derain
