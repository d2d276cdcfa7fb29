#pragma once
// Registering the frames of a slowly panning camera onto one reference frame, so that the
// static background lines up for Eq. (1), and warping the results back.
#include <vector>

#include <opencv2/core.hpp>

#include "derain/frame_stack.h"

namespace pluvia::derain {

// What a homography fit leaves of a panning camera's motion at the background's edges
// (parallax, rolling shutter, resampling), in pixels: DerainSettings::registrationErrorPx for
// frames registered by warpToReference.
constexpr double kResidualMisregistrationPx = 0.5;

// A frame's motion where a homography leaves parallax (a camera moving past things at several
// depths): dense flow on the rain-suppressed greys, after the homography.
struct DenseMotion {
  cv::Mat2f toFrame;           // on the reference grid: each pixel's position in the frame
  cv::Mat1b validOnReference;  // 255 where that position is inside the frame and consistent
  cv::Mat2f toReference;       // on the frame's grid: each pixel's position on the reference grid
  cv::Mat1b validOnFrame;      // 255 where the reference saw the pixel, consistently
  bool empty() const { return toFrame.empty(); }
};

struct Registration {
  // Per frame: the homography taking reference-frame pixel coordinates to that frame's pixel
  // coordinates (identity for the reference frame itself).
  std::vector<cv::Matx33d> referenceToFrame;
  // Largest displacement of a frame corner under any of the homographies, in pixels.
  double maxShiftPx = 0.0;
  // The camera was found locked off before any feature matching: every homography is identity.
  bool lockedOff = false;
  // Frames that could not be registered (too few feature matches) and took the motion of a
  // registered neighbour, placedWith's frame at the same place (indices into the frames given).
  std::vector<int> placedFrames, placedWith;
  // What the fitted motion explains (measured when it moved a frame by kStaticShiftPx): the mean
  // absolute difference of the rain-suppressed frames from the reference's (8-bit codes of
  // featureImage), with the frames as they are and resampled by the motion. The motion is kept
  // only when it leaves clearly less (motionRejected otherwise: every homography is identity).
  double identityResidual = 0.0;
  double motionResidual = 0.0;
  bool motionRejected = false;
  // Per frame (empty where the homography alone is kept, and for a camera not moving()): the
  // dense refinement, taken where it lowers the frame's rain-suppressed residual after the
  // homography clearly (registration.cpp says by how much). `homographyResidual` and
  // `flowResidual` are those residuals over the refined frames (0 when none was).
  std::vector<DenseMotion> dense;
  int denseFrames() const;
  double homographyResidual = 0.0, flowResidual = 0.0;
  bool moving() const { return !motionRejected && maxShiftPx >= 0.25; }
};

// Estimates each frame's homography from frames[reference]. First, from evidence: when phase
// correlation of the median-filtered luminance finds no quadrant of any frame shifted by a
// quarter pixel, the camera is locked off and every homography is the identity (no feature is
// matched, nothing is resampled). Otherwise ORB features on the median-filtered luminance (thin
// rain streaks carry none; ratio test; RANSAC). A frame with too few matches takes its nearest
// registered neighbour's homography and is listed in placedFrames (the caller, who knows the
// clip's frame numbers, says so). When no frame moves more than half a pixel every homography is
// the identity. Then by what the motion explains: it is kept only where it lowers the
// rain-suppressed temporal residual to under kClearlyLowerResidual of the residual of the frames
// as they are (repeated texture, a façade's windows, can fit a motion on a camera that never
// moved).
// Last, where the motion is kept: each frame's dense refinement (Registration::dense), unless
// `denseFlow` is false (the homography alone, as `pluvia report derain` compares).
inline constexpr double kClearlyLowerResidual = 0.8;
Registration registerFrames(const std::vector<cv::Mat>& frames, int reference,
                            bool denseFlow = true);

// The last step of registerFrames: measures registration's identityResidual and motionResidual
// on `frames` and, unless the motion leaves under kClearlyLowerResidual of the residual without
// it, sets motionRejected and every homography to the identity (maxShiftPx is kept, to say what
// was rejected).
void keepMotionThatExplains(const std::vector<cv::Mat>& frames, int reference,
                            Registration& registration);

// The frames resampled onto the reference frame's pixel grid, with validity masks (by the dense
// motion where a frame has one: occluded and inconsistent pixels are invalid). When the
// registration is not moving() the frames are passed through untouched (no resampling blur).
FrameStack warpToReference(const std::vector<cv::Mat>& frames, const Registration& registration);

// An image on the reference grid resampled onto frame `index`'s grid (bilinear; by the dense
// motion where the frame has one); pixels of that frame outside the reference frame (or, with
// dense motion, not seen consistently by it: disoccluded) come back as 0, and `covered`
// (CV_8UC1, when given) says which pixels were inside.
cv::Mat warpToFrame(const cv::Mat& onReference, const Registration& registration, int index,
                    cv::Mat* covered = nullptr);

}  // namespace pluvia::derain
