#pragma once
// Synthetic ground truth for rain extraction: rain of known matte, colour and direction
// composited over a real static image by I = (1 - alpha) S + alpha C, plus sensor noise. The
// streaks are drawn here independently of the solver: anti-aliased segments of random length,
// width and opacity along one direction, at random positions, fresh in every frame.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/frame_stack.h"

namespace pluvia::lab {

struct SyntheticRainSettings {
  int frames = 20;
  double angleDeg = 12.0;            // frame_stack.h convention
  double streaksPerMegapixel = 900;  // per frame
  double minLengthPx = 15, maxLengthPx = 60;
  double minWidthPx = 1.0, maxWidthPx = 2.5;
  double minAlpha = 0.15, maxAlpha = 0.5;   // peak opacity of a streak
  cv::Vec3f rainColor{0.85f, 0.87f, 0.9f};  // C; each frame varies it by +-3 %
  double noiseSigma = 0.01;                 // Gaussian sensor noise per channel, 0..1
  uint64_t seed = 1;
};

struct SyntheticRain {
  cv::Mat background;                // S, CV_32FC3 (the input image; the first frame's)
  std::vector<cv::Mat> backgrounds;  // per frame (all the same for a still background)
  derain::FrameStack stack;          // the rained, noisy frames
  std::vector<cv::Mat> alpha;        // true alpha per frame, CV_32FC1
  std::vector<cv::Vec3f> rainColor;  // true C per frame
  double angleDeg = 0.0;
};

// `background`: CV_32FC3 RGB in 0..1, in the values the solver works on (frame_stack.h: the
// display encoding of 8-bit footage), where the blend, the colour and the noise all apply. The
// rained frames are clamped to [0, 1] like a camera's (saturated rain pixels included); before that
// clamp each frame is exactly (1 - alpha) S + alpha C^k plus the noise. Streaks that overlap
// combine as one layer of colour C^k: alpha = 1 - prod(1 - a_i). Frame k depends only on (seed, k),
// not on the frame count. Throws pluvia::Error on an empty or non-CV_32FC3 background or
// inconsistent settings.
SyntheticRain makeSyntheticRain(const cv::Mat& background, const SyntheticRainSettings& settings);
// The same rain over a moving background: frame k over backgrounds[k] (one per frame, one size).
SyntheticRain makeSyntheticRainOver(const std::vector<cv::Mat>& backgrounds,
                                    const SyntheticRainSettings& settings);

}  // namespace pluvia::lab
