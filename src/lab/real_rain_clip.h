#pragma once
// Real rain footage as `pluvia report realism` and `pluvia match` measure it: the clip's first
// frames at the measuring width, a clean plate per frame (derain/clean_plate.h), and the
// statistics of the rain layers frame - plate (derain/streak_stats.h).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/clean_plate.h"
#include "derain/streak_stats.h"

namespace pluvia::lab {

// Real rain footage whose frame rate is not stored (NTURain's JPEGs) is taken at this rate.
inline constexpr double kUnknownFps = 25.0;

struct RealClip {
  std::string name;  // its file name, or its folder's for a sequence named by numbers only
  double fps = kUnknownFps;
  std::vector<cv::Mat3f> frames;  // RGB, 8-bit display codes, at the measuring width
  int filmedWidthPx = 0;          // the footage's own width: the camera that filmed the rain
};

// NTURain ra1 in the shared data (a sequence pattern); empty when it is not there.
std::string defaultClip(const std::string& sharedData);

// The clip's first `count` frames (all when fewer), in display codes, scaled to `widthPx`.
// Throws pluvia::Error naming the file when it has fewer than 3 frames or cannot be read.
RealClip readRealClip(const std::string& path, int count, int widthPx);

// clean_plate.h works on BGR frames: the same plates for RGB ones (codes), of the frames `at`
// (every frame when empty).
std::vector<derain::CleanPlate> cleanPlatesRgb(const std::vector<cv::Mat3f>& rgbFrames,
                                               const std::vector<int>& at = {});

// The statistics of the layers frame - plate over the clip (luma in codes); `layersOut`, when
// given, receives each frame's layer.
derain::StreakStats measureLayers(const std::vector<cv::Mat3f>& frames,
                                  const std::vector<derain::CleanPlate>& plates,
                                  std::vector<cv::Mat1f>* layersOut = nullptr);

}  // namespace pluvia::lab
