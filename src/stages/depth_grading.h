#pragma once
// What the rain between the camera and the scene does to the plate grows with the path through
// it: darken and blur take the weight w(z) = 1 - exp(-z / distance) of the frame's depth z (the
// "depth" plane, metres; +inf, the sky, and a frame without depth weigh 1), so the near field
// changes less than the far and nothing is lifted or lowered alike over the whole frame.
// distance 0 weighs every pixel 1 (the whole frame alike, as before depth grading).
//
// Each grading stage writes what it changed as its own AOV (`--aov darken,blur,fog`: planes
// "<name>.R/G/B" = after - before, "<name>.A" = the weight), so the plate plus the AOVs rebuilds
// the graded frame in comp.
#include <functional>
#include <string>
#include <vector>

#include "image/image.h"
#include "pipeline/stage.h"

namespace pluvia {

// w(z) per pixel, as above.
std::vector<float> depthGradingWeights(const Image& image, double distanceMeters);

// Records one stage's change to the frame as its AOV when the render asked for it (its planes
// exist: the render session makes them before the stages run). Construct before the change,
// call finish() after it.
class GradingAov {
 public:
  GradingAov(const Image& image, std::string name);
  // Writes after - before and `weight` (may be empty: 1 where anything changed).
  void finish(Image& image, const std::vector<float>& weight) const;

 private:
  std::string name_;
  std::vector<float> before_;  // RGBA; empty when the AOV was not asked for
};

// A grading stage (darken, blur): `grade` changes the frame by the per-pixel weight w(z) of
// `distanceMeters`, and the change is recorded as AOV `name` when asked for. On a plate shot in
// rain it leaves the frames as they are unless `overRain` (stages/clip_plate_rain.h).
class DepthGradingStage : public Stage {
 public:
  using Grade = std::function<void(Image& image, const std::vector<float>& weight)>;
  DepthGradingStage(std::string name, double distanceMeters, bool overRain, Grade grade)
      : name_(std::move(name)),
        distanceMeters_(distanceMeters),
        overRain_(overRain),
        grade_(std::move(grade)) {}
  void prepareAhead(ClipContext& clip) override;
  void prepare(ClipContext& clip) override;
  void process(ClipContext&, FrameContext& frame) override;

 private:
  std::string name_;
  double distanceMeters_;
  bool overRain_;
  Grade grade_;
  bool leftOut_ = false;
  // The weights of the last frame and the depth they were made from: a depth that stays (a
  // guess, layers, a locked-off camera) is not weighed again every frame.
  const std::vector<float>& weightsOf(const Image& image);
  std::vector<float> weights_;
  std::vector<float> weightsDepth_;
};

}  // namespace pluvia
