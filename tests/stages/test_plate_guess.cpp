// What the default stages guess from the plate alone: the depth (sky at infinity, the ground
// under the camera, a backdrop for the rest) and the lighting (the frame within its view, the
// frame's own sky or a CIE overcast sky above it, the airlight at the horizon).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "envmap/frame_environment.h"
#include "image/equirect.h"
#include "stages/depth_guess.h"

using namespace pluvia;

namespace {

constexpr int kWidth = 64, kHeight = 48;

TEST(DepthGuess, SkyIsInfiniteGroundFollowsTheCameraTheRestIsTheBackdrop) {
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 40.0, 10.0, 1.6);
  std::vector<uint8_t> sky(size_t(kWidth) * kHeight, 0);
  for (int x = 0; x < kWidth; ++x) sky[size_t(x)] = 1;  // the top row
  const DepthGuess guess = guessDepth(sky, camera, 20.0);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const float depth = guess.depthMeters[size_t(y) * kWidth + x];
      if (y == 0) {
        EXPECT_EQ(depth, std::numeric_limits<float>::infinity());
        continue;
      }
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      const double ground = ray.y() < 0 ? 1.6 / -ray.y() : 1e9;
      EXPECT_NEAR(depth, std::min(ground, 20.0), 1e-4 * std::min(ground, 20.0)) << x << "," << y;
    }
  EXPECT_NEAR(guess.skyFraction, 1.0 / kHeight, 1e-9);
  EXPECT_GT(guess.groundFraction, 0.3);  // tilted down 10 deg: most of the lower frame
  // A camera on the ground (height 0) sees no ground plane: all backdrop.
  const DepthGuess flat =
      guessDepth(sky, Camera::fromFieldOfView(kWidth, kHeight, 40.0, 10.0, 0.0), 20.0);
  EXPECT_EQ(flat.groundFraction, 0.0);
  EXPECT_EQ(flat.depthMeters.back(), 20.0f);
}

Image twoToneFrame(float top, float bottom) {
  Image frame(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = y < kHeight / 3 ? top : bottom;
  return frame;
}

TEST(FrameEnvironment, TheFramesOwnSkyLightsFromAbove) {
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  std::vector<uint8_t> sky(size_t(kWidth) * kHeight, 0);
  for (int y = 0; y < kHeight / 3; ++y)
    for (int x = 0; x < kWidth; ++x) sky[size_t(y) * kWidth + x] = 1;
  const envmap::FrameEnvironment env =
      envmap::frameEnvironment(twoToneFrame(0.9f, 0.1f), camera, sky);
  // Straight up: the frame's sky; straight down: the frame's bottom rows; ahead, slightly
  // below the horizon: the frame itself.
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, 1, 0)[0], 0.9f, 1e-4);
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, -1, 0)[0], 0.1f, 1e-4);
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, -0.2f, -1)[0], 0.1f, 1e-3);
  EXPECT_NEAR(env.horizonRgb[1], 0.9f, 1e-4);
}

TEST(FrameEnvironment, NoSkyInTheFrameGivesTheOvercastSkyThatLightsIt) {
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const Image frame = twoToneFrame(0.2f, 0.2f);  // a grey wall, luminance 0.2
  const envmap::FrameEnvironment env = envmap::frameEnvironment(frame, camera, {});
  // CIE overcast: Lz = 9/7 * 0.2 / 0.18; the horizon a third of it.
  const double zenith = 9.0 / 7.0 * 0.2 / 0.18;
  EXPECT_NEAR(env.horizonRgb[0], zenith / 3.0, 1e-4);
  const float up = sampleEquirect(env.radiance, 0, 1, 0)[0];
  EXPECT_NEAR(up, zenith, 0.03 * zenith);  // the top row's centre is just off the zenith
  // The sky is brighter than what it lights, so drops against the wall show.
  EXPECT_GT(up, 5.0f * 0.2f);
  for (float v : env.radiance.rgb) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
