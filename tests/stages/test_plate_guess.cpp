// What the default stages guess from the plate alone: the depth (sky at infinity, the ground
// under the camera, a backdrop for the rest) and the lighting (the frame within its view, the
// frame's own sky or a CIE overcast sky above it, the airlight at the horizon).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "envmap/frame_environment.h"
#include "image/equirect.h"
#include "optics/fresnel.h"
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

std::vector<uint8_t> topThirdSky() {
  std::vector<uint8_t> sky(size_t(kWidth) * kHeight, 0);
  for (int y = 0; y < kHeight / 3; ++y)
    for (int x = 0; x < kWidth; ++x) sky[size_t(y) * kWidth + x] = 1;
  return sky;
}

// The mean elevation (degrees, 0 at least) the sky pixels are seen at.
double meanSkyElevationDeg(const Camera& camera, const std::vector<uint8_t>& sky) {
  double sum = 0.0, count = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (!sky[size_t(y) * kWidth + x]) continue;
      const Eigen::Vector3d d =
          (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
      sum += std::max(0.0, std::asin(d.y()) * 180.0 / M_PI);
      count += 1.0;
    }
  return sum / count;
}

// Lz of the CIE overcast sky under which upright surfaces of albedo 0.125 (the metered albedo,
// independent of the code) that see 2/3 of it have `luminance`: sky (2/3)(pi/4 + 2/3) Lz plus the
// ground's 0.125 * (7 pi / 9) Lz / 2, times 2/3.
double sceneZenith(double luminance) {
  const double upright = 2.0 / 3.0 * (M_PI / 4.0 + 2.0 / 3.0) + 0.125 * 7.0 * M_PI / 9.0 / 2.0;
  return M_PI * luminance / (0.125 * 2.0 / 3.0 * upright);
}

TEST(FrameEnvironment, TheOvercastSkyGoesThroughTheFramesOwnSky) {
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const std::vector<uint8_t> sky = topThirdSky();
  const envmap::FrameEnvironment env =
      envmap::frameEnvironment(twoToneFrame(0.9f, 0.05f), camera, sky, false);
  // The CIE overcast profile L(e) = Lz (1 + 2 sin e) / 3 through the plate's sky (0.9) at the
  // mean elevation it is seen at: brighter than the plate above it, darker at the horizon.
  const double e0 = meanSkyElevationDeg(camera, sky) * M_PI / 180.0;
  const double zenith = 3.0 * 0.9 / (1.0 + 2.0 * std::sin(e0));
  ASSERT_GT(zenith, sceneZenith(0.05));  // the plate's sky is the brighter estimate here
  EXPECT_NEAR(env.zenithLuminance, zenith, 1e-4);
  EXPECT_TRUE(env.skyFromPlate);
  EXPECT_NEAR(env.horizonRgb[1], 0.9f, 1e-4);  // the airlight: the plate's own sky
  const float up = sampleEquirect(env.radiance, 0, 1, 0)[0];
  EXPECT_NEAR(up, zenith, 0.03 * zenith);  // the top row's centre is just off the zenith
  // Ahead, slightly below the horizon: the frame itself.
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, -0.2f, -1)[0], 0.05f, 1e-3);
  // Straight down, more than 60 deg below the frame: wet level ground of albedo 0.125 seeing 2/3
  // of the overcast sky (radiance 0.125 (2/3) (7/9) Lz), plus water's Fresnel reflectance at
  // normal incidence (0.020) of the sky straight up (the map's rows at +-88.6 deg).
  const double rowElevation = (90.0 - 180.0 * 0.5 / 64.0) * M_PI / 180.0;
  const double fresnel = optics::fresnelReflectance(std::sin(rowElevation), 1.333);
  ASSERT_NEAR(fresnel, 0.0204, 0.0005);
  const double ground = (1.0 - fresnel) * 0.125 * 2.0 / 3.0 * 7.0 / 9.0 * zenith +
                        fresnel * zenith * (1.0 + 2.0 * std::sin(rowElevation)) / 3.0;
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, -1, 0)[0], ground, 1e-3 * ground);
}

TEST(FrameEnvironment, TheGroundBelowTheFrameFadesFromTheFramesBottomRow) {
  // A dark hedge at the frame's bottom (0.02) under a bright scene: just below the frame the map
  // is still nearly the hedge, 60 deg further down the ground the sky lights; in between it
  // rises steadily (a log-space blend), never under the hedge nor over the ground.
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const envmap::FrameEnvironment env =
      envmap::frameEnvironment(twoToneFrame(0.3f, 0.02f), camera, {}, false);
  float previous = 0.0f;
  for (double e = -25.0; e >= -85.0; e -= 10.0) {
    const float v = sampleEquirect(env.radiance, 0, float(std::sin(e * M_PI / 180.0)),
                                   -float(std::cos(e * M_PI / 180.0)))[0];
    EXPECT_GE(v, previous) << e;
    previous = v;
  }
  EXPECT_LT(sampleEquirect(env.radiance, 0, -0.45f, -0.89f)[0], 2.0 * 0.02);  // 27 deg down
  // 85 deg down: the ground, and the sky 85 deg up at water's Fresnel reflectance there (0.020),
  // which is 30 % of it under a sky 15 times brighter than the scene.
  const double lz = env.zenithLuminance, up = 85.0 * M_PI / 180.0;
  const double fresnel = optics::fresnelReflectance(std::sin(up), 1.333);
  const double ground = (1.0 - fresnel) * 0.125 * 2.0 / 3.0 * 7.0 / 9.0 * lz +
                        fresnel * lz * (1.0 + 2.0 * std::sin(up)) / 3.0;
  EXPECT_NEAR(previous, ground, 0.03 * ground);
}

TEST(FrameEnvironment, ADimPlateSkyIsNoDarkerThanTheSkyThatLightsTheScene) {
  // A clipped or knee-compressed sky records darker than it is: a plate whose sky reads 0.5 over
  // a scene of 0.3 gets the sky that lights that scene.
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const envmap::FrameEnvironment env =
      envmap::frameEnvironment(twoToneFrame(0.5f, 0.3f), camera, topThirdSky(), false);
  EXPECT_NEAR(env.zenithLuminance, sceneZenith(0.3), 1e-3);
  EXPECT_FALSE(env.skyFromPlate);
  // The plate's own sky is lifted onto that sky: a uniform 0.5 becomes the overcast sky at the
  // mean elevation it is seen at, not the clip a drop would otherwise refract, and the map has no
  // step at the frame's top edge.
  const double e0 = meanSkyElevationDeg(camera, topThirdSky()) * M_PI / 180.0;
  const double lifted = env.zenithLuminance * (1.0 + 2.0 * std::sin(e0)) / 3.0;
  ASSERT_GT(lifted, 1.5 * 0.5);
  const float inFrame =
      sampleEquirect(env.radiance, 0, float(std::sin(e0)), -float(std::cos(e0)))[0];
  EXPECT_NEAR(inFrame, lifted, 0.02 * lifted);
  // The frame's top edge is 18.4 deg up (50 deg across 4:3): just inside and just above it.
  const auto at = [&](double deg) {
    const double r = deg * M_PI / 180.0;
    return sampleEquirect(env.radiance, 0, float(std::sin(r)), -float(std::cos(r)))[0];
  };
  // (The plate's sky is uniform, the model rises by (1 + 2 sin 21 deg) / (1 + 2 sin e0).)
  EXPECT_NEAR(at(16.0) / at(21.0), (1.0 + 2.0 * std::sin(e0)) / (1.0 + 2.0 * std::sin(0.3665)),
              0.05);
  // The airlight stays what the plate recorded: the fog is laid over the plate.
  EXPECT_NEAR(env.horizonRgb[0], 0.5f, 1e-4);
}

TEST(FrameEnvironment, AClearBlueSkyIsTakenAsThePlateShowsIt) {
  // A blue sky (linear 0.15 0.35 0.8: saturation 0.81) over a sunlit scene of 0.3: the sun lights
  // the scene, and the plate has measured the sky, so it is not lifted to the overcast sky that
  // would light that scene (sceneZenith(0.3), 5 times brighter here); the ground below the frame
  // is still lit as brightly as the scene.
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  Image frame = twoToneFrame(0.3f, 0.3f);
  const float blue[3] = {0.15f, 0.35f, 0.8f};
  for (int y = 0; y < kHeight / 3; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = blue[c];
  const envmap::FrameEnvironment env =
      envmap::frameEnvironment(frame, camera, topThirdSky(), false);
  EXPECT_TRUE(env.clearSky);
  const double luminance = 0.2126 * 0.15 + 0.7152 * 0.35 + 0.0722 * 0.8;
  const double e0 = meanSkyElevationDeg(camera, topThirdSky()) * M_PI / 180.0;
  const double zenith = 3.0 * luminance / (1.0 + 2.0 * std::sin(e0));
  ASSERT_LT(5.0 * zenith, sceneZenith(0.3));
  EXPECT_NEAR(env.zenithLuminance, zenith, 1e-4);
  // The plate's sky as it shows it, and the sky above it blue too.
  EXPECT_NEAR(sampleEquirect(env.radiance, 0, float(std::sin(e0)), -float(std::cos(e0)))[2], 0.8f,
              0.02f);
  const std::array<float, 3> up = sampleEquirect(env.radiance, 0, 1, 0);
  EXPECT_NEAR(up[2] / up[0], 0.8 / 0.15, 0.05 * 0.8 / 0.15);
  // Straight down: wet ground of albedo 0.125 lit in white as the scene is (under
  // sceneZenith(0.3)), plus water's Fresnel reflectance (0.020) of the blue sky straight up.
  const double rowElevation = (90.0 - 180.0 * 0.5 / 64.0) * M_PI / 180.0;
  const double fresnel = optics::fresnelReflectance(std::sin(rowElevation), 1.333);
  const std::array<float, 3> down = sampleEquirect(env.radiance, 0, -1, 0);
  for (int c = 0; c < 3; ++c) {
    const double ground =
        (1.0 - fresnel) * 0.125 * 2.0 / 3.0 * 7.0 / 9.0 * sceneZenith(0.3) +
        fresnel * zenith * (1.0 + 2.0 * std::sin(rowElevation)) / 3.0 * blue[c] / luminance;
    EXPECT_NEAR(down[size_t(c)], ground, 0.01 * ground) << c;
  }
  // The same sky grey (saturation 0) is an overcast one, lifted as before.
  const envmap::FrameEnvironment grey =
      envmap::frameEnvironment(twoToneFrame(0.3f, 0.3f), camera, topThirdSky(), false);
  EXPECT_FALSE(grey.clearSky);
  EXPECT_NEAR(grey.zenithLuminance, sceneZenith(0.3), 1e-3);
}

TEST(FrameEnvironment, NoSkyInTheFrameGivesTheOvercastSkyThatLightsIt) {
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const Image frame = twoToneFrame(0.2f, 0.2f);  // a grey wall, luminance 0.2
  const envmap::FrameEnvironment env = envmap::frameEnvironment(frame, camera, {}, false);
  const double zenith = sceneZenith(0.2);
  EXPECT_NEAR(env.horizonRgb[0], zenith / 3.0, 1e-4);
  const float up = sampleEquirect(env.radiance, 0, 1, 0)[0];
  EXPECT_NEAR(up, zenith, 0.03 * zenith);  // the top row's centre is just off the zenith
  // The sky is brighter than what it lights, so drops against the wall show.
  EXPECT_GT(up, 10.0f * 0.2f);
  for (float v : env.radiance.rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(FrameEnvironment, ANightPlatesSkyIsOnlyWhatThePlateShows) {
  // Lamps light a night scene, not the sky: no overcast sky above, so drops far from the lamps
  // stay as dark as the night.
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 50.0, 0.0, 1.6);
  const envmap::FrameEnvironment withSky =
      envmap::frameEnvironment(twoToneFrame(0.02f, 0.05f), camera, topThirdSky(), true);
  EXPECT_NEAR(sampleEquirect(withSky.radiance, 0, 1, 0)[0], 0.02f, 1e-5);
  EXPECT_NEAR(withSky.zenithLuminance, 0.02f, 1e-5);
  const envmap::FrameEnvironment noSky =
      envmap::frameEnvironment(twoToneFrame(0.05f, 0.05f), camera, {}, true);
  EXPECT_NEAR(sampleEquirect(noSky.radiance, 0, 1, 0)[0], 0.05f, 1e-5);
}

}  // namespace
