#pragma once
// Rain extraction, Wang et al. Eq. (1): the static background S and the per-frame rain mattes
// alpha^k of a stack of registered frames,
//   min_{S,alpha} sum_{i,j,k} (I^k_ij - (1 - alpha^k_i) S_ij - alpha^k_i C^k_j)^2
//                 + lambda sum_{i,j} |grad S_ij|^2 + mu sum_{i,k} (grad alpha^k_i . D0)^2,
// solved by alternating minimisation (the paper's EM) started from the temporal median:
// alpha (per frame, S fixed), then D0 from alpha's spectrum, then the rain colour C^k (closed
// form), then S (alpha fixed). Each quadratic sub-problem is a sparse SPD system solved by
// Jacobi-preconditioned conjugate gradients.
// alpha is then projected onto [0, 1] and zeroed where the rain it claims, |alpha (C - S)|,
// lies within three noise sigmas (see registrationErrorPx; clipping noise at 0 alone would keep its
// positive half as rain and bias S low). The solver works in 8-bit code values (FrameStack's 0..1
// times 255), the units of the paper's video: mu = 1/4 weighs (grad alpha . D0)^2 against intensity
// squared, so the paper's values mean what they meant there only in those units.
#include <vector>

#include "derain/frame_stack.h"

namespace pluvia::derain {

struct DerainSettings {
  double lambda = 1.0 / 20.0;     // weight of |grad S|^2 (the paper's 1/20)
  double mu = 1.0 / 4.0;          // weight of (grad alpha . D0)^2 (the paper's 1/4)
  int maxIterations = 8;          // EM iterations; 0 returns the median initialisation
  double tolerance = 1e-3;        // stop when the objective falls by less than this fraction
  int cgMaxIterations = 300;      // cap on each conjugate-gradient solve
  double cgTolerance = 1e-5;      // relative residual at which a conjugate-gradient solve stops
  bool estimateDirection = true;  // false: D0 stays at initialAngleDeg
  double initialAngleDeg = 0.0;   // D0 starts vertical
  // Residual misregistration of the frames, pixels: 0 for a locked-off camera. Where the
  // background has a gradient g, alpha below 3 * sqrt(noise^2 + (this * g)^2) is taken as noise.
  double registrationErrorPx = 0.0;
};

struct DerainIteration {
  int iteration = 0;          // 0: the median initialisation
  double objective = 0.0;     // Eq. (1) per pixel per frame (all three terms), code values^2
  double dataRms = 0.0;       // RMS of the data term's residual I - (1-alpha)S - alpha C, 0..1
  double angleDeg = 0.0;      // D0 after this iteration
  double seconds = 0.0;       // wall time since the solve began
  int cgIterationsAlpha = 0;  // largest count over the frames' alpha solves
  int cgIterationsS = 0;      // largest count over the three channels' S solves
};

struct DerainResult {
  cv::Mat background;                // S, CV_32FC3
  std::vector<cv::Mat> alpha;        // alpha^k, CV_32FC1 in [0, 1]
  std::vector<cv::Vec3f> rainColor;  // C^k (R, G, B)
  double angleDeg = 0.0;             // D0 (frame_stack.h convention)
  // Whether D0 came from the mattes' spectrum (a salient line in some iteration); false: it
  // stayed at DerainSettings::initialAngleDeg (no rain direction seen, or not estimated).
  bool angleFound = false;
  int iterations = 0;       // EM iterations run
  double residual = 0.0;    // final dataRms
  double noiseSigma = 0.0;  // robust (MAD) estimate of the per-channel sensor noise
  std::vector<DerainIteration> history;
};

// Throws pluvia::Error when the stack has fewer than 3 frames or frames of different sizes.
// Never returns NaN: non-finite input pixels are treated as invalid.
DerainResult solveDerain(const FrameStack& stack, const DerainSettings& settings = {});

// The per-pixel temporal median of the valid samples (the paper's initialisation and the
// baseline of Starik and Werman / Garg and Nayar), CV_32FC3.
cv::Mat temporalMedian(const FrameStack& stack);

}  // namespace pluvia::derain
