#pragma once
// A clean plate per frame of real rain footage: the background the rain fell in front of, so
// that frame - plate is the real rain layer streak_stats.h measures.
//
// For frame t, the 2r + 1 frames around it (the window shifted, not shrunk, at the clip's ends)
// are registered onto it and the plate is their per-pixel median: rain is thin, bright and moves
// fast, so at any pixel only a few frames of the stack hold it.
//
// Registration works on rain-suppressed greys (a grey-scale opening with a 5 px disk, which
// removes structures narrower than 5 px brighter than their surround: the streaks). Per
// neighbour it decides by evidence between identity (locked-off camera) and dense flow
// (cv::DISOpticalFlow, PRESET_MEDIUM): the flow is taken only when it lowers the residual (the
// mean absolute difference of the greys, its largest 10 % left out) clearly, since on a still
// camera it only fits noise and moving objects. Where flow is used, it follows moving objects too:
// they are then in the plate, not masked.
//
// Frames are BGR float in 8-bit display codes (0..255 scale); the order matters only for the
// registration grey (Rec. 709 luma weights).
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::derain {

struct CleanPlateSettings {
  int radiusFrames = 3;            // r: the stack holds up to 2r + 1 frames
  int suppressDiameterPx = 5;      // of the opening's disk
  double flowGainFraction = 0.10;  // flow is used when it lowers the residual by more than this
  double flowGainCodes = 0.5;      // ... and by more than this
  double consistencyPx = 1.0;      // forward-backward flow error above which a pixel is dropped
  double agreementCodes = 12.0;    // stack and frame agreement (below)
  int distrustMarginPx = 3;        // pixels this near a disagreeing one are not valid either
};

struct NeighbourRegistration {
  int frame = 0;  // index in the clip
  bool flowUsed = false;
  // Mean |difference| of the rain-suppressed greys, the largest 10 % left out.
  double identityResidualCodes = 0.0;
  double flowResidualCodes = 0.0;  // ... after warping by the flow, over the pixels it covers
};

struct CleanPlate {
  cv::Mat3f plate;  // BGR, codes
  // 255 where the plate can be trusted: at least r + 1 registered frames cover the pixel (in
  // bounds and, where flow was used, forward-backward consistent; others are left out of the
  // median), the stack agrees (median absolute deviation of its rain-suppressed greys under
  // agreementCodes), and the frame's own rain-suppressed grey is within agreementCodes of the
  // stack's median. The last catches moving objects, which the robust MAD cannot when they
  // cover a pixel in fewer than half the frames; rain does not fail it, being suppressed. The
  // invalid areas wider than the suppression's disk (objects, not a broad streak) are grown by
  // distrustMarginPx: a walker's soft outline passes the test yet leaves a residue that reads as
  // bright streaks (on the example street it raised the reference's peak p90 from 38 to 45 codes).
  cv::Mat1b valid;
  std::vector<NeighbourRegistration> neighbours;  // in clip order, frame t left out
};

// One plate per frame. Throws pluvia::Error when the frames are empty or differ in size.
std::vector<CleanPlate> cleanPlates(const std::vector<cv::Mat3f>& frames,
                                    const CleanPlateSettings& settings = {});
// The plates of the frames `at` (indices into `frames`) only, in that order; the same errors,
// and one naming an index outside the frames.
std::vector<CleanPlate> cleanPlatesAt(const std::vector<cv::Mat3f>& frames,
                                      const std::vector<int>& at,
                                      const CleanPlateSettings& settings = {});

}  // namespace pluvia::derain
