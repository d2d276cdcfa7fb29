// The ground's AOVs add back to the beauty: the wet_ground and splash stages, run on a grey
// plate of level ground below a wall and the sky under a uniform environment, write what they
// changed (RGB) and where (A), and the frame before them plus their AOV is the frame after them
// within float rounding. Wet ground darkens the ground and leaves the wall and the sky exactly;
// splashes land on the ground only.
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

// 1 m above the ground, 45 degrees down, 20 degrees across: the ground 1.4 m away, where a
// crown spans a few pixels.
Camera groundCamera() {
  return Camera::fromFieldOfView(kWidth, kHeight, 20.0, 45.0, 1.0);
}

// Grey level ground on the left two thirds, a vertical wall facing the camera 0.6 m ahead on the
// right third (its top rows the sky).
constexpr double kWallMeters = 0.6;
constexpr int kSkyRows = 8;
Image plate() {
  const Camera camera = groundCamera();
  Image image(kWidth, kHeight);
  std::vector<float>& depth = image.plane("depth");
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      float* p = image.pixel(x, y);
      const float shade = 0.15f + 0.05f * float((x / 4 + y / 4) % 2);  // a texture to darken
      p[0] = shade;
      p[1] = 0.9f * shade;
      p[2] = 0.8f * shade;
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      float& z = depth[size_t(y) * kWidth + x];
      if (x < 2 * kWidth / 3)
        z = float(camera.positionMeters.y() / -ray.y());
      else
        z = y < kSkyRows ? std::numeric_limits<float>::infinity() : float(kWallMeters / -ray.z());
    }
  return image;
}

Image run(const std::string& stageName, const std::vector<std::string>& sets) {
  const Preset preset = Preset::resolve("base", sets, presetSchema());
  std::unique_ptr<Stage> stage = findStage(stageName)->create(preset);
  ClipContext clip;
  clip.fps = 24.0;
  Environment environment;
  environment.radiance = uniformEquirect(64, 32, {1.0f, 1.0f, 1.0f});
  clip.environment = environment;
  clip.cameraPath = CameraPath::fixed(groundCamera());
  stage->prepare(clip);
  FrameContext frame;
  frame.frame = 12;
  frame.image = plate();
  for (const char* c : {"R", "G", "B", "A"}) frame.image.plane(stageName + "." + c);
  stage->process(clip, frame);
  return std::move(frame.image);
}

// The largest |before + AOV - after| over the frame's RGB, and the pixels the stage changed on
// the ground and on the wall (not the sky above it, where a droplet thrown up may show).
struct AddBack {
  double worst = 0.0;
  int changedGround = 0, changedWall = 0;
};
AddBack addBack(const Image& before, const Image& after, const std::string& aov) {
  AddBack result;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      bool changed = false;
      for (int c = 0; c < 3; ++c) {
        const float change = after.rgba[i * 4 + c] - before.rgba[i * 4 + c];
        changed = changed || change != 0.0f;
        const float recorded = after.findPlane(aov + "." + "RGB"[c])->at(i);
        result.worst = std::max(result.worst, double(std::abs(change - recorded)));
      }
      if (changed && x < 2 * kWidth / 3) ++result.changedGround;
      if (changed && x >= 2 * kWidth / 3 && y >= kSkyRows) ++result.changedWall;
    }
  return result;
}

}  // namespace

TEST(GroundAovs, WetGroundDarkensTheGroundOnlyAndItsAovAddsBack) {
  const Image before = plate();
  const Image after = run("wet_ground", {"rain.rate_mm_h=10"});
  const AddBack check = addBack(before, after, "wet_ground");
  EXPECT_LT(check.worst, 1e-6);
  EXPECT_EQ(check.changedWall, 0) << "the wall stays dry";
  EXPECT_EQ(check.changedGround, 2 * kWidth / 3 * kHeight);
  // Seen 45 degrees down under a uniform sky of 1 the ground's albedo is about 0.17: wet, its own
  // light falls to about half (over the guessed depth of the base preset the film mirrors
  // nothing).
  const size_t centre = size_t(kHeight / 2) * kWidth + kWidth / 3;
  EXPECT_LT(after.rgba[centre * 4], before.rgba[centre * 4] * 0.8f);
  EXPECT_EQ(after.findPlane("wet_ground.A")->at(centre), 1.0f);
}

TEST(GroundAovs, SplashesLandOnTheGroundAndTheirAovAddsBack) {
  const Image before = plate();
  const Image after = run("splash", {"rain.rate_mm_h=100", "camera.exposure_s=0.02"});
  const AddBack check = addBack(before, after, "splash");
  EXPECT_LT(check.worst, 1e-6);
  EXPECT_GT(check.changedGround, 10);
  EXPECT_EQ(check.changedWall, 0) << "no splash on the wall, which is nearer than the ground";
  double coverage = 0.0;
  for (const float a : *after.findPlane("splash.A")) coverage += a;
  EXPECT_GT(coverage, 1.0);
}
