#pragma once
// Derain over a whole clip: frames read (in the file's own encoding, see frame_stack.h), cut into
// windows of `window` frames, a quarter of each solved again by the next and cross-faded (the
// last window reaches back so every window is full), each window
// registered (panning camera) and solved with Eq. (1); results handed back frame by frame on
// each frame's own pixel grid.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "derain/derain_solver.h"

namespace pluvia::derain {

struct ClipDerainSettings {
  DerainSettings solver;
  int window = 20;                 // frames per solve, at least 3
  int64_t firstFrame = INT64_MIN;  // frame range (inclusive); defaults: the whole clip
  int64_t lastFrame = INT64_MAX;
  bool registration = true;  // false: assume a locked-off camera
  // The rain's direction when known beforehand (a first pass over the clip): windows whose
  // mattes do not show it keep this one until a window sees it (ClipDerainFrame::angleCarried).
  std::optional<double> knownAngleDeg;
};

struct ClipDerainFrame {
  int64_t frame = 0;  // the clip's frame number
  cv::Mat original;   // the frame as read, CV_32FC3 RGB
  // S on this frame's grid; where the window's reference frame did not see the pixel, the frame
  // itself median-filtered (5 px)
  cv::Mat clean;
  cv::Mat matte;            // alpha on this frame's grid, CV_32FC1 (0 outside the reference frame)
  cv::Mat covered;          // CV_8UC1, nonzero where the window's reference frame saw this pixel
  cv::Vec3f rainColor;      // C^k
  double angleDeg = 0.0;    // the window's D0
  bool angleFound = false;  // D0 was seen in the window's mattes (DerainResult::angleFound)
  // Not seen there, but kept from an earlier window that saw it; neither: D0 is the solver's
  // vertical start, a guess.
  bool angleCarried = false;
  double noiseSigma = 0.0;
};

// One window's solve, without its images (they went to `emit`).
struct ClipDerainWindow {
  int64_t firstFrame = 0, lastFrame = 0;
  double maxShiftPx = 0.0;  // registration: 0 when not registered
  // Which registration was taken ("locked off", "identity", "identity (the motion explained
  // less)", "motion" or "motion, dense flow on N frames") and the residuals it was chosen by
  // (Registration; 0 when not measured).
  std::string registration;
  double identityResidual = 0.0, motionResidual = 0.0;
  double angleDeg = 0.0;
  bool angleFound = false;  // DerainResult::angleFound
  int iterations = 0;
  double residual = 0.0;
  double noiseSigma = 0.0;
  std::vector<DerainIteration> history;
};

struct ClipDerainSummary {
  std::vector<ClipDerainWindow> windows;
  // Over the frames of the windows whose mattes showed the rain's direction; 0 (vertical, the
  // solver's start) when none did.
  double angleDeg = 0.0;
  size_t windowsWithAngle = 0;
  double angleMinDeg = 0.0, angleMaxDeg = 0.0;  // over those windows
  cv::Vec3f rainColor;                          // mean C over all frames
  int iterations = 0;                           // largest over windows
  double residual = 0.0;                        // RMS over windows
  double seconds = 0.0;
};

// "rain angle -33.0 deg (found in 3 of 4 windows, -35.2 to -31.0 deg)", or that no window's
// mattes showed it.
std::string describeRainAngle(const ClipDerainSummary& summary);

// Calls `emit` once per frame, in frame order. Throws pluvia::Error naming the input when the
// range holds fewer than 3 frames or a frame cannot be read or registered.
ClipDerainSummary derainClip(const std::string& input, const ClipDerainSettings& settings,
                             const std::function<void(const ClipDerainFrame&)>& emit);

}  // namespace pluvia::derain
