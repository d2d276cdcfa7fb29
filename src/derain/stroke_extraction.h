#pragma once
// Cutting single rain strokes out of derained mattes (Wang et al. section 2): each matte is
// rotated so the rain is vertical, blurred vertically (along the rain), thresholded above its
// noise and split into connected components. Each component is a candidate stroke, turned
// exactly upright and trimmed, and rejected when it is too short,
// not elongated, tilted, bent, broken, unlike a clean streak, clipped by the frame edge, lying
// on an edge of the scene or still there in a neighbouring frame (static structure the solve
// left in the matte); the rest are ranked by contrast, length, slimness, isolation and
// cleanness (formula in stroke_extraction.cpp).
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/clip_derain.h"
#include "rain/stroke_library.h"

namespace pluvia::derain {

struct StrokeExtractionSettings {
  int count = 64;          // strokes kept, best first
  int minLengthPx = 9;     // shorter streaks (their own length, the blur taken out): no strokes
  double minAspect = 2.4;  // length over width
  // The upright matte is blurred along the rain by a Gaussian of this sigma: a matched filter
  // for streaks, which keeps a long faint streak (one the solve's noise dead zone broke into
  // dashes) whole and spreads a speck thin.
  double blurSigmaPx = 3.0;
  // A component of the blurred matte must exceed this many times its noise level (and at least
  // minContrast), so footage without rain yields no strokes. The noise level is the larger of
  // the solve's noiseSigma and the matte's own (from its upper quartile), each as the blur
  // leaves it.
  double noiseFactor = 6.0;
  double minContrast = 0.02;
  int isolationMarginPx = 6;  // margin around a stroke's box searched for other strokes
  // A stroke's own axis may differ from the clip's rain direction by this much (wind, the
  // estimate's error); it is then turned upright on its own. More: not a rain stroke.
  double maxTiltDeg = 10.0;
  double maxBendPx = 1.0;  // RMS distance of its row centres from a straight line
  // Normalised correlation with an ideal straight streak of its own length profile and width
  // (forks, zigzags, a blob beside it lower it); below this: not one clean stroke.
  double minFidelity = 0.97;
  // Static structure that leaks into the mattes (edges the registration left, thin lines of the
  // scene) stays put from frame to frame while rain moves on: a stroke is rejected when a
  // neighbouring frame (the one before or the one after), once the camera's motion between the
  // two is undone, holds more than maxStaticShare of its patch of matte (1 - least squared
  // difference over the patch's energy) within staticTolerancePx (parallax, the motion
  // estimate's error).
  int staticTolerancePx = 6;
  double maxStaticShare = 0.5;
  // A matte the solver leaves on an edge of the scene (a registration error of a pixel times the
  // edge's gradient) lies along that edge; rain falls over edges and flat areas alike. With a
  // background given, a stroke is rejected when the background's gradient along it (the mean
  // over its rows of the largest gradient magnitude across the row, intensity per pixel)
  // exceeds maxBackgroundEdge times its contrast.
  double maxBackgroundEdge = 0.1;
};

class StrokeCollector {
 public:
  explicit StrokeCollector(StrokeExtractionSettings settings);
  ~StrokeCollector();
  StrokeCollector(StrokeCollector&&) noexcept;
  StrokeCollector& operator=(StrokeCollector&&) noexcept;

  // One frame's matte (CV_32FC1, 0..1) on the frame's grid, the rain angle and the noise level
  // of the solve (DerainResult::noiseSigma) it came from. `background` (optional, CV_32FC3 or
  // CV_32FC1: the derained frame S on the same grid) lets strokes that lie on edges of the
  // scene be told from rain (see maxBackgroundEdge). `valid` (optional, CV_8UC1, nonzero where
  // the matte was solved) marks the area whose border counts as the frame's edge; empty: the
  // whole frame. Frames come in clip order: each is compared with the one added before and
  // the one added after it, so a frame's strokes are cut when the next one arrives (or in
  // finish()).
  void addFrame(int64_t frame, const cv::Mat& matte, double angleDeg, double noiseSigma,
                const cv::Mat& background = cv::Mat(), const cv::Mat& valid = cv::Mat());
  // The best `count` strokes packed into one atlas (possibly fewer, possibly none: then the
  // atlas is empty, 0 x 0). Cuts the last frame first; call it once, after the last frame.
  rain::StrokeLibrary finish();
  // Components that passed every test, over the frames cut so far (all of them after finish).
  size_t candidateCount() const;

 private:
  struct Candidate;
  struct Frame;
  void cut(const Frame& frame, const std::vector<const Frame*>& neighbours);

  StrokeExtractionSettings settings_;
  std::vector<Frame> recent_;          // the last frames added, up to three
  std::vector<Candidate> candidates_;  // the best ones seen so far (a bounded number)
  size_t accepted_ = 0;
};

// Derain a clip (clip_derain.h) and cut strokes from every frame's matte.
struct ClipStrokes {
  rain::StrokeLibrary library;  // possibly empty: the caller says what that means
  size_t candidates = 0;
  size_t frames = 0;
  // Of those, the frames cut: the ones whose window saw the rain's direction or kept an earlier
  // window's (ClipDerainFrame::angleCarried).
  size_t framesCut = 0;
  double angleDeg = 0.0;         // ClipDerainSummary's
  std::string angleDescription;  // describeRainAngle's
};
ClipStrokes cutStrokesFromClip(const std::string& input, const ClipDerainSettings& clip,
                               const StrokeExtractionSettings& extraction);

}  // namespace pluvia::derain
