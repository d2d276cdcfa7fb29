// Darken, blur and fog grade the plate by depth (stages/depth_grading.h): far pixels change more
// than near ones, and each stage's AOV (what it changed) adds back to the graded frame.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pipeline/stage.h"
#include "preset/preset.h"
#include "stages/depth_grading.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

constexpr int kWidth = 64, kHeight = 48;
constexpr float kNearMeters = 2.0f, kFarMeters = 80.0f;

// A textured plate (a checker of 4 px cells in two colours) whose left half is near and right
// half far, the top eight rows sky.
Image plateWithDepth() {
  Image image(kWidth, kHeight);
  std::vector<float>& depth = image.plane("depth");
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      float* p = image.pixel(x, y);
      const bool light = ((x / 4) + (y / 4)) % 2 == 0;
      p[0] = light ? 0.8f : 0.05f;
      p[1] = light ? 0.6f : 0.10f;
      p[2] = light ? 0.3f : 0.02f;
      depth[size_t(y) * kWidth + x] = y < 8 ? std::numeric_limits<float>::infinity()
                                            : (x < kWidth / 2 ? kNearMeters : kFarMeters);
    }
  return image;
}

// The mean |change| of RGB over a rectangle of rows 8.. (no sky).
double meanChange(const Image& before, const Image& after, int x0, int x1) {
  double sum = 0.0;
  int n = 0;
  for (int y = 8; y < kHeight; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c, ++n)
        sum += std::abs(after.pixel(x, y)[c] - before.pixel(x, y)[c]);
  return sum / n;
}

// Runs one stage (by its section's name) of a preset over `image`.
void runStage(const std::string& name, const Preset& preset, Image& image) {
  for (const StageInfo& info : allStages()) {
    if (info.spec.name != name) continue;
    std::unique_ptr<Stage> stage = info.create(preset);
    ClipContext clip;
    stage->prepare(clip);
    FrameContext frame;
    frame.image = std::move(image);
    stage->process(clip, frame);
    image = std::move(frame.image);
    return;
  }
  FAIL() << "no stage " << name;
}

Preset preset(const std::vector<std::string>& sets) {
  return Preset::resolve("base", sets, presetSchema());
}

}  // namespace

TEST(DepthGrading, WeightsGrowWithDepthAndAreOneForSky) {
  const Image plate = plateWithDepth();
  const std::vector<float> w = depthGradingWeights(plate, 30.0);
  EXPECT_FLOAT_EQ(w[0], 1.0f);  // sky
  EXPECT_NEAR(w[size_t(20) * kWidth + 1], 1.0 - std::exp(-2.0 / 30.0), 1e-6);
  EXPECT_NEAR(w[size_t(20) * kWidth + 60], 1.0 - std::exp(-80.0 / 30.0), 1e-6);
  for (float v : depthGradingWeights(plate, 0.0)) EXPECT_EQ(v, 1.0f);  // 0: all alike
}

class GradingStage : public ::testing::TestWithParam<const char*> {};

TEST_P(GradingStage, ChangesFarPixelsMoreThanNearOnesAndItsAovAddsBack) {
  const std::string name = GetParam();
  const Preset p = preset({"darken.amount=0.5", "blur.sigma_px=2", "fog.density=0.02",
                           "fog.color_source=constant", "fog.color=[0.7,0.7,0.75]"});
  const Image plate = plateWithDepth();
  Image graded = plate;
  for (const char* c : {".R", ".G", ".B", ".A"}) graded.plane(name + c);  // --aov NAME
  runStage(name, p, graded);
  const double nearChange = meanChange(plate, graded, 4, kWidth / 2 - 4);
  const double farChange = meanChange(plate, graded, kWidth / 2 + 4, kWidth - 4);
  EXPECT_GT(nearChange, 0.0) << name;
  EXPECT_GT(farChange, 3.0 * nearChange)
      << name << ": near " << nearChange << ", far " << farChange;
  // plate + AOV = graded frame, every pixel and channel.
  double worst = 0.0;
  for (size_t i = 0; i < plate.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float delta = graded.plane(name + "." + std::string(1, "RGB"[c]))[i];
      worst = std::max(worst, double(std::abs(plate.rgba[i * 4 + size_t(c)] + delta -
                                              graded.rgba[i * 4 + size_t(c)])));
    }
  EXPECT_LT(worst, 1e-6) << name;
}

INSTANTIATE_TEST_SUITE_P(DarkenBlurFog, GradingStage, ::testing::Values("darken", "blur", "fog"));

TEST(DepthGrading, DistanceZeroGradesEveryPixelAlike) {
  // The old look on request: darken.distance_m = 0 darkens near and far alike.
  const Preset p = preset({"darken.amount=0.5", "darken.distance_m=0"});
  const Image plate = plateWithDepth();
  Image graded = plate;
  runStage("darken", p, graded);
  EXPECT_NEAR(meanChange(plate, graded, 4, kWidth / 2 - 4),
              meanChange(plate, graded, kWidth / 2 + 4, kWidth - 4), 0.02);
}

TEST(DepthGrading, NoAovPlanesWithoutTheRequest) {
  const Preset p = preset({"darken.amount=0.5"});
  Image graded = plateWithDepth();
  runStage("darken", p, graded);
  EXPECT_EQ(graded.findPlane("darken.R"), nullptr);
}

// One stage over a clip keeps the weights while the depth stays and weighs again when it
// changes: each frame comes out as a fresh stage grades it alone.
TEST(DepthGrading, AStageOverFramesWeighsEachFramesOwnDepth) {
  const Preset p = preset({"darken.amount=0.5", "blur.sigma_px=2"});
  for (const char* name : {"darken", "blur"}) {
    const StageInfo* info = nullptr;
    for (const StageInfo& candidate : allStages())
      if (candidate.spec.name == name) info = &candidate;
    ASSERT_NE(info, nullptr) << name;
    std::unique_ptr<Stage> stage = info->create(p);
    ClipContext clip;
    stage->prepare(clip);
    Image swapped = plateWithDepth();  // near and far swapped, then no depth at all
    for (float& z : swapped.plane("depth"))
      z = z == kNearMeters ? kFarMeters : z == kFarMeters ? kNearMeters : z;
    Image withoutDepth = plateWithDepth();
    withoutDepth.planes.erase("depth");
    for (const Image& plate :
         {plateWithDepth(), plateWithDepth(), swapped, withoutDepth, plateWithDepth()}) {
      FrameContext frame;
      frame.image = plate;
      stage->process(clip, frame);
      Image alone = plate;
      runStage(name, p, alone);
      EXPECT_EQ(frame.image.rgba, alone.rgba) << name;
    }
  }
}
