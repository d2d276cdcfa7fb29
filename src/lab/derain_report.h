#pragma once
// `pluvia report derain`: how well rain extraction (Wang et al. Eq. 1, derain_solver.h) recovers
// a known background, matte and rain direction, against the temporal-median baseline, and at
// what cost.
//
//  (a) Synthetic ground truth (synthetic_rain.h) over real still backgrounds at a few rain
//      angles: the median baseline and solveDerain on the same 20 frames.
//  (b) Error against run time: the solver stopped after 0 (the median initialisation), 1, 2,
//      4, 8 EM iterations (tolerance 0), and over windows of 3, 5, 10, 20 frames.
//  (a') A camera moving past two depths (lab/parallax_clip.h) with synthetic rain, against the
//      middle frame's clean image: the flow-registered median (derain/clean_plate.h), the solve
//      after a homography alone, and the default (dense flow where the homography leaves
//      parallax).
//  (c) Real rain footage of a panning camera, registered onto its middle frame, then solved:
//      the objective, data residual and rain angle per iteration (no ground truth there).
//
// Measures. Backgrounds, rain and noise are all in display encoding, the values the solver works
// on (frame_stack.h), and S is compared with the true background there (clamped to [0, 1]):
// PSNR (peak 1) and SSIM.
// alpha MAE is the mean |alpha - true alpha| over every pixel of every frame. The median
// baseline's matte is implied by its background: the positive luminance residual over the
// headroom to white, alpha = clamp(Y(I - S) / (1 - Y(S)), 0, 1), rain taken as white as in
// Garg-Nayar and Starik-Werman; its rain angle is estimateRainAngle of those mattes. Times are
// wall clock for everything the method needs to produce S, alpha and the angle.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/derain_solver.h"

namespace pluvia::lab {

struct DerainReportSettings {
  std::string examplePlate;  // the backgrounds' first: a frame of the repo's example plate
  std::string sharedData;    // ../shared/data; empty or missing: only the example plate
  std::string imagesDir;     // when set: previews written here as PNG
  bool quick = false;        // one case at 320x240, short sweeps, no real footage (for tests)
  int frames = 20;           // per synthetic case (and real-footage window)
  uint64_t seed = 1;
  derain::DerainSettings solver;  // the "solver" rows' settings
};

struct DerainReportRow {
  std::string section;  // "synthetic", "moving", "iterations", "window"
  std::string scene;    // background: "street", "lund", "weir"
  double trueAngleDeg = 0.0;
  // "input" (no derain: frame 0 as S; moving: the middle frame), "median", "solver", "default"
  // (registration decided from evidence), "homography" (moving: no dense flow)
  std::string method;
  int frames = 0;
  int iterations = 0;   // EM iterations run (solver rows)
  double psnrDb = 0.0;  // display encoding
  double ssim = 0.0;
  double alphaMae = 0.0;
  double angleDeg = 0.0;       // estimated rain angle (NaN for "input")
  double angleErrorDeg = 0.0;  // |estimate - truth| folded into [0, 90] (NaN for "input")
  double seconds = 0.0;        // NaN for "input"
  double objective = 0.0;      // final Eq. (1) per pixel per frame (solver rows; NaN otherwise)
  double dataRms = 0.0;        // final data residual (solver rows; NaN otherwise)
};

struct DerainRealFootage {
  bool present = false;
  std::string path;
  int frames = 0;
  cv::Size size;
  int reference = 0;  // index in the window of the frame everything is registered onto
  double maxShiftPx = 0.0;
  double registrationSeconds = 0.0;
  double medianAngleDeg = 0.0;  // derain::estimateRainAngle of the median baseline's implied mattes
  derain::DerainResult result;  // the solve (its images on the reference frame's grid)
  double solveSeconds = 0.0;
  double meanAlpha = 0.0;
};

struct DerainReport {
  cv::Size size;  // of the synthetic frames
  int frames = 0;
  double noiseSigma = 0.0;  // synthetic sensor noise (display encoding)
  std::vector<DerainReportRow> rows;
  DerainRealFootage real;
  std::vector<std::string> notes;  // missing data, images written
};

// Throws pluvia::Error naming the file when the example plate cannot be read or an image
// cannot be written. Missing shared data is not an error: a note says what was left out.
DerainReport runDerainReport(const DerainReportSettings& settings);

std::string formatDerainReport(const DerainReport& report);
// One line per row; the real footage's iterations as rows of section "real" whose columns
// without a ground truth are empty.
void writeDerainReportCsv(const DerainReport& report, const std::string& path);
// PSNR of S (dB) against run time (s, log): the iteration sweep and the window sweep as lines,
// the median baseline as markers.
void writeDerainReportPlot(const DerainReport& report, const std::string& path);

}  // namespace pluvia::lab
