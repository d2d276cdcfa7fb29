// The wet ground (rain/wet_ground.h) on synthetic scenes whose answers are known: level ground
// is wholly wet, a wall and the sky are not, a slope between the full and the dry tilt is wet by
// the linear share of its cosine; a uniform sky's level irradiance is pi times its radiance; and
// a grey ground under a uniform sky becomes, pixel by pixel, Lekner and Dorf's darkening plus
// Fresnel's share of the sky, computed here by hand from the formulas of optics/wet_surface.h.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "optics/fresnel.h"
#include "rain/wet_ground.h"

using namespace pluvia;

namespace {

constexpr int kWidth = 64, kHeight = 48;
constexpr double kEta = 1.333;
// The ground's first row under the horizon (131 m, its neighbour below at half that, above it
// the sky) shows no surface to take a normal from: the checks stop short of it.
constexpr float kResolvedMeters = 50.0f;

// 1.5 m above the ground, pitched 20 degrees down, 60 degrees across: the horizon crosses the
// upper part of the frame.
Camera streetCamera() {
  return Camera::fromFieldOfView(kWidth, kHeight, 60.0, 20.0, 1.5);
}

Eigen::Vector3d ray(const Camera& camera, int x, int y) {
  return camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
}

// z-depth of the plane through `point` with unit normal `normal` along pixel (x, y); +inf when
// the ray misses it (the sky).
float planeDepth(const Camera& camera, int x, int y, const Eigen::Vector3d& point,
                 const Eigen::Vector3d& normal) {
  const Eigen::Vector3d r = ray(camera, x, y);  // camera-space z = -1 scaled: depth = t
  const double denominator = r.dot(normal);
  const double t = (point - camera.positionMeters).dot(normal) / denominator;
  return denominator < 0.0 && t > 0.0 ? float(t) : std::numeric_limits<float>::infinity();
}

std::vector<float> depthOfPlane(const Camera& camera, const Eigen::Vector3d& normal) {
  std::vector<float> depth(size_t(kWidth) * kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      depth[size_t(y) * kWidth + x] = planeDepth(camera, x, y, Eigen::Vector3d::Zero(), normal);
  return depth;
}

}  // namespace

TEST(WetGround, LevelGroundIsWetAndTheSkyIsNot) {
  const Camera camera = streetCamera();
  const std::vector<float> depth = depthOfPlane(camera, Eigen::Vector3d::UnitY());
  const std::vector<float> weights = rain::wetGroundWeights(camera, depth, 30.0, 15.0);
  int ground = 0, sky = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] < kResolvedMeters) {
      EXPECT_NEAR(weights[i], 1.0f, 1e-4f) << "ground pixel " << i;
      ++ground;
    } else if (!std::isfinite(depth[i])) {
      EXPECT_EQ(weights[i], 0.0f) << "sky pixel " << i;
      ++sky;
    }
  }
  EXPECT_GT(ground, 1000);
  EXPECT_GT(sky, 100);
}

TEST(WetGround, AWallIsDryAndASlopeWetByItsShareOfTheFade) {
  const Camera camera = streetCamera();
  // A wall facing the camera, 5 m ahead.
  std::vector<float> wall(size_t(kWidth) * kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      wall[size_t(y) * kWidth + x] =
          planeDepth(camera, x, y, Eigen::Vector3d(0, 0, -5), Eigen::Vector3d::UnitZ());
  for (const float w : rain::wetGroundWeights(camera, wall, 30.0, 15.0)) EXPECT_EQ(w, 0.0f);
  // Ground rising towards the camera's view at 37.5 degrees: halfway through the fade in angle,
  // the share of the fade in cosine.
  const double tilt = 37.5 * M_PI / 180.0;
  const Eigen::Vector3d normal(0.0, std::cos(tilt), std::sin(tilt));
  const std::vector<float> slope = depthOfPlane(camera, normal);
  const std::vector<float> weights = rain::wetGroundWeights(camera, slope, 30.0, 15.0);
  const double full = std::cos(30.0 * M_PI / 180.0), none = std::cos(45.0 * M_PI / 180.0);
  const double expected = (std::cos(tilt) - none) / (full - none);
  int checked = 0;
  for (size_t i = 0; i < slope.size(); ++i) {
    if (!std::isfinite(slope[i])) continue;
    EXPECT_NEAR(weights[i], expected, 2e-3) << "pixel " << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(WetGround, AUniformSkysLevelIrradianceIsPiTimesItsRadiance) {
  const std::array<double, 3> e =
      rain::levelIrradiance(uniformEquirect(64, 32, {2.0f, 1.0f, 0.5f}));
  EXPECT_NEAR(e[0], 2.0 * M_PI, 1e-5);
  EXPECT_NEAR(e[1], M_PI, 1e-5);
  EXPECT_NEAR(e[2], 0.5 * M_PI, 1e-5);
}

TEST(WetGround, GreyGroundUnderAUniformSkyDarkensAndMirrorsItByHand) {
  const Camera camera = streetCamera();
  const std::vector<float> depth = depthOfPlane(camera, Eigen::Vector3d::UnitY());
  const std::vector<float> weights = rain::wetGroundWeights(camera, depth, 30.0, 15.0);
  const float sky = 1.0f, ground = 0.1f;  // albedo pi * 0.1 / (pi * 1) = 0.1
  rain::WetGroundLight light;
  light.gloss = uniformEquirect(64, 32, {sky, sky, sky});
  light.irradiance = {M_PI * sky, M_PI * sky, M_PI * sky};
  Image image(kWidth, kHeight);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = std::isfinite(depth[i]) ? ground : sky;
  const Image dry = image;
  rain::wetGround(image, weights, rain::levelFilmView(camera, weights, light, kEta), 1.0, 1.0,
                  light, kEta);
  // By hand: Rbar for water 0.0664 (2 int R mu dmu, as tests/optics checks), p = 1 - (1 - Rbar) /
  // eta^2.
  const double rbar = 0.06641, p = 1.0 - (1.0 - rbar) / (kEta * kEta), albedo = 0.1;
  int checked = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (!std::isfinite(depth[i])) {
        EXPECT_EQ(image.rgba[i * 4], dry.rgba[i * 4]) << "the sky is left as it is";
        continue;
      }
      if (depth[i] > kResolvedMeters) continue;
      const double mu = std::abs(ray(camera, x, y).normalized().y());
      const double r = optics::fresnelReflectance(mu, kEta);
      const double expected =
          ground * (1.0 - rbar) * (1.0 - r) / (kEta * kEta * (1.0 - p * albedo)) + r * sky;
      EXPECT_NEAR(image.rgba[i * 4 + 1], expected, 2e-4) << x << "," << y;
      EXPECT_EQ(image.rgba[i * 4 + 3], 1.0f) << "alpha is kept";
      ++checked;
    }
  EXPECT_GT(checked, 1000);
  // Wetness 0 leaves the plate exactly.
  Image again = dry;
  rain::wetGround(again, weights, rain::levelFilmView(camera, weights, light, kEta), 0.0, 1.0,
                  light, kEta);
  EXPECT_EQ(again.rgba, dry.rgba);
}

TEST(WetGround, GrassSoaksTheWaterInAndOnlyDarkens) {
  const float grass[3] = {0.05f, 0.12f, 0.04f};  // saturation 0.67: no film
  const float asphalt[3] = {0.08f, 0.08f, 0.08f};
  const float brick[3] = {0.3f, 0.24f, 0.2f};  // saturation 0.33
  EXPECT_EQ(rain::filmCoverage(grass), 0.0);
  EXPECT_EQ(rain::filmCoverage(asphalt), 1.0);
  EXPECT_NEAR(rain::filmCoverage(brick), 0.0, 1e-6);
  const float concrete[3] = {0.4f, 0.38f, 0.34f};  // saturation 0.15: half a film
  EXPECT_NEAR(rain::filmCoverage(concrete), 0.5, 1e-6);
  // On grass under a bright sky the pixel darkens by the film's ratio alone.
  const Camera camera = streetCamera();
  const std::vector<float> depth = depthOfPlane(camera, Eigen::Vector3d::UnitY());
  const std::vector<float> weights = rain::wetGroundWeights(camera, depth, 30.0, 15.0);
  rain::WetGroundLight light;
  light.gloss = uniformEquirect(64, 32, {10.0f, 10.0f, 10.0f});
  light.irradiance = {10.0 * M_PI, 10.0 * M_PI, 10.0 * M_PI};
  Image image(kWidth, kHeight);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = grass[c];
  const Image dry = image;
  rain::wetGround(image, weights, rain::levelFilmView(camera, weights, light, kEta), 1.0, 1.0,
                  light, kEta);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    if (depth[i] < kResolvedMeters)
      for (int c = 0; c < 3; ++c) EXPECT_LT(image.rgba[i * 4 + c], 0.6f * dry.rgba[i * 4 + c]);
}

// Lekner and Dorf's darkening is per wavelength: a channel of lower albedo loses more, so wet
// ground is more saturated than dry (real wet grass is deeper green, not greyer).
TEST(WetGround, EachChannelDarkensByItsOwnAlbedoSoWetGroundIsMoreSaturated) {
  const Camera camera = streetCamera();
  const std::vector<float> depth = depthOfPlane(camera, Eigen::Vector3d::UnitY());
  const std::vector<float> weights = rain::wetGroundWeights(camera, depth, 30.0, 15.0);
  rain::WetGroundLight light;
  light.gloss = uniformEquirect(64, 32, {0.0f, 0.0f, 0.0f});  // nothing mirrored
  light.irradiance = {M_PI, M_PI, M_PI};
  const float grass[3] = {0.3f, 0.6f, 0.1f};  // albedos, the light's radiance 1
  Image image(kWidth, kHeight);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = grass[c];
  rain::wetGround(image, weights, rain::levelFilmView(camera, weights, light, kEta), 1.0, 0.0,
                  light, kEta);
  const double rbar = 0.06641, p = 1.0 - (1.0 - rbar) / (kEta * kEta);
  int checked = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (!(depth[i] < kResolvedMeters)) continue;
      const double r =
          optics::fresnelReflectance(std::abs(ray(camera, x, y).normalized().y()), kEta);
      for (int c = 0; c < 3; ++c) {
        const double expected =
            grass[c] * (1.0 - rbar) * (1.0 - r) / (kEta * kEta * (1.0 - p * grass[c]));
        EXPECT_NEAR(image.rgba[i * 4 + c], expected, 2e-5) << x << "," << y << " channel " << c;
      }
      const float* wet = image.pixel(x, y);
      EXPECT_GT((wet[1] - wet[2]) / wet[1], (grass[1] - grass[2]) / grass[1] + 0.02f);
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}
