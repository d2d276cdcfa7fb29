// The ripples stage (stages/ripples_stage.cpp) over level water seen from 1 m above, looking
// 60 degrees down, under a sky that brightens with elevation: rings appear on the water only,
// their AOV (what the stage changed) adds back to the frame, the frame after them is the same
// however it was reached, and a rate of 0 leaves the plate exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/camera_path.h"
#include "pipeline/stage.h"
#include "preset/preset.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

constexpr int kWidth = 96, kHeight = 64;

// A narrow view (8 degrees: 16 cm of water across), so that its pixels resolve the crests.
Camera waterCamera() {
  return Camera::fromFieldOfView(kWidth, kHeight, 8.0, 60.0, 1.0);
}

// A grey plate whose left half is level water (the ground at y = 0) and right half a wall 0.5 m
// away: the wall takes no rings.
Image plate() {
  const Camera camera = waterCamera();
  Image image(kWidth, kHeight);
  std::vector<float>& depth = image.plane("depth");
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      float* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = 0.2f;
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      depth[size_t(y) * kWidth + x] =
          x < kWidth / 2 ? float(camera.positionMeters.y() / -ray.y()) : 0.5f;
    }
  return image;
}

Environment skyGrowingWithElevation() {
  Environment environment;
  environment.radiance = EquirectMap(64, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const float elevation = float(M_PI * (0.5 - (y + 0.5) / 32.0));
      for (int c = 0; c < 3; ++c)
        environment.radiance.texel(x, y)[c] = 4.0f * std::max(0.0f, std::sin(elevation));
    }
  return environment;
}

Image run(const std::vector<std::string>& sets, int64_t frameNumber, bool aov) {
  const Preset preset = Preset::resolve("base", sets, presetSchema());
  std::unique_ptr<Stage> stage = findStage("ripples")->create(preset);
  ClipContext clip;
  clip.fps = 24.0;
  clip.environment = skyGrowingWithElevation();
  clip.cameraPath = CameraPath::fixed(waterCamera());
  stage->prepare(clip);
  FrameContext frame;
  frame.frame = frameNumber;
  frame.image = plate();
  if (aov)
    for (const char* c : {"R", "G", "B", "A"}) frame.image.plane(std::string("ripples.") + c);
  stage->process(clip, frame);
  return std::move(frame.image);
}

const std::vector<std::string> kOn = {"ripples.enabled=true", "rain.rate_mm_h=50"};

}  // namespace

TEST(RipplesStage, RingsOnTheWaterOnlyAndTheirAovAddsBack) {
  const Image before = plate();
  Image after = run(kOn, 30, true);
  int changedWater = 0;
  double worst = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      const float change = after.rgba[i * 4] - before.rgba[i * 4];
      if (x >= kWidth / 2) EXPECT_EQ(change, 0.0f) << "the wall at " << x << "," << y;
      if (std::abs(change) > 1e-4f) ++changedWater;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, double(std::abs(before.rgba[i * 4 + c] +
                                                after.plane(std::string("ripples.") + "RGB"[c])[i] -
                                                after.rgba[i * 4 + c])));
    }
  EXPECT_GT(changedWater, 20);
  EXPECT_LT(worst, 1e-6);
}

TEST(RipplesStage, AFrameIsTheSameAloneAndNoRainLeavesThePlate) {
  const Image first = run(kOn, 30, false), again = run(kOn, 30, false);
  EXPECT_EQ(first.rgba, again.rgba);
  const Image dry = run({"ripples.enabled=true", "rain.rate_mm_h=0"}, 30, false);
  EXPECT_EQ(dry.rgba, plate().rgba);
}
