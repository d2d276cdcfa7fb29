// The rainbow: Descartes angles, the rendered bows' angles per channel (within 1 deg of the
// Descartes angle of the channel's eta), the order of their colours, occlusion by depth, the
// sun found in an environment, and the cases where no bow can show.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geometry/camera.h"
#include "lab/test_environment.h"
#include "optics/drop_shading.h"
#include "optics/rainbow.h"
#include "rain/drop_physics.h"
#include "stages/rainbow_render.h"
#include "stages/sun.h"

using namespace pluvia;

namespace {

constexpr double kDeg = M_PI / 180.0;

// A sun 2 deg up behind a camera looking level along -Z: the antisolar point lies 2 deg below
// the frame's centre, and the bows' tops in the centre column.
struct BowScene {
  Camera camera = Camera::fromFieldOfView(400, 300, 120.0, 0.0, 1.6);
  Sun sun{sunDirection(2.0, 180.0), {3.0, 3.0, 3.0}};
  RainbowVolume volume{rain::rainExtinctionPerMeter(15.0), 0.0, 2000.0, 1.0};
  std::array<optics::RainbowProfile, 3> profiles =
      optics::rainbowProfiles(optics::kWaterEtaDispersion);

  Image render(const std::vector<float>* depth = nullptr) const {
    Image image(camera.width, camera.height);
    if (depth) image.plane("depth") = *depth;
    addRainbow(image, camera, sun, profiles, volume);
    return image;
  }
  // Scattering angle (from the sun's direction of travel) of pixel centre (x, y).
  double scatteringDeg(int x, int y) const {
    const Eigen::Vector3d v =
        (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
    return 180.0 - std::acos(std::clamp(v.dot(-sun.direction), -1.0, 1.0)) / kDeg;
  }
  // The scattering angle of channel c's brightest pixel in the centre column within [lo, hi].
  double peakDeg(const Image& image, int c, double lo, double hi) const {
    const int x = camera.width / 2;
    double best = -1.0, at = 0.0;
    for (int y = 0; y < camera.height; ++y) {
      const double theta = scatteringDeg(x, y);
      if (theta < lo || theta > hi) continue;
      const float v = image.pixel(x, y)[c];
      if (v > best) best = v, at = theta;
    }
    return at;
  }
};

}  // namespace

TEST(Rainbow, DescartesAnglesOfWater) {
  // Textbook values for eta = 1.333: primary 137.9 deg (42.1 from the antisolar point),
  // secondary 129.4 deg (50.6).
  EXPECT_NEAR(optics::descartesScatteringDeg(1, 1.333), 137.9, 0.3);
  EXPECT_NEAR(optics::descartesScatteringDeg(2, 1.333), 129.4, 0.3);
  // Higher eta bends more: blue's primary lies nearer the antisolar point (larger angle).
  EXPECT_GT(optics::descartesScatteringDeg(1, 1.338), optics::descartesScatteringDeg(1, 1.331));
}

TEST(Rainbow, ProfilePeaksAtTheDescartesAngles) {
  for (double eta : optics::kWaterEtaDispersion) {
    const optics::RainbowProfile p = optics::rainbowProfile(eta);
    auto peak = [&](double lo, double hi) {
      double best = -1.0, at = 0.0;
      for (double t = lo; t <= hi; t += 0.01)
        if (p.at(t) > best) best = p.at(t), at = t;
      return at;
    };
    EXPECT_NEAR(peak(133.0, 145.0), optics::descartesScatteringDeg(1, eta), 1.0) << eta;
    EXPECT_NEAR(peak(122.0, 133.0), optics::descartesScatteringDeg(2, eta), 1.0) << eta;
    // Alexander's dark band between the bows holds neither term's light.
    EXPECT_LT(p.at(133.5), 0.05 * p.at(peak(133.0, 145.0))) << eta;
  }
}

TEST(Rainbow, RenderedBowsAtTheirAnglesWithColoursInOrder) {
  const BowScene scene;
  const Image image = scene.render();
  std::array<double, 3> primary{}, secondary{};
  for (int c = 0; c < 3; ++c) {
    const double eta = optics::kWaterEtaDispersion[size_t(c)];
    primary[size_t(c)] = scene.peakDeg(image, c, 133.0, 145.0);
    secondary[size_t(c)] = scene.peakDeg(image, c, 122.0, 133.0);
    EXPECT_NEAR(primary[size_t(c)], optics::descartesScatteringDeg(1, eta), 1.0) << c;
    EXPECT_NEAR(secondary[size_t(c)], optics::descartesScatteringDeg(2, eta), 1.0) << c;
  }
  // Primary: red outside (smaller scattering angle, farther from the antisolar point) than blue;
  // secondary: the reverse.
  EXPECT_LT(primary[0], primary[2]);
  EXPECT_GT(secondary[0], secondary[2]);
  // The primary is brighter than the secondary.
  const int x = scene.camera.width / 2;
  double top1 = 0.0, top2 = 0.0;
  for (int y = 0; y < scene.camera.height; ++y) {
    const double t = scene.scatteringDeg(x, y);
    if (t > 133.0 && t < 145.0) top1 = std::max(top1, double(image.pixel(x, y)[1]));
    if (t > 122.0 && t < 133.0) top2 = std::max(top2, double(image.pixel(x, y)[1]));
  }
  EXPECT_GT(top1, 1.5 * top2);
}

TEST(Rainbow, NearerSceneDepthHidesTheFarRain) {
  const BowScene scene;
  std::vector<float> depth(size_t(scene.camera.width) * scene.camera.height,
                           std::numeric_limits<float>::infinity());
  // A wall 1 m away over the left half of the frame.
  for (int y = 0; y < scene.camera.height; ++y)
    for (int x = 0; x < scene.camera.width / 2; ++x)
      depth[size_t(y) * size_t(scene.camera.width) + size_t(x)] = 1.0f;
  const Image open = scene.render(), walled = scene.render(&depth);
  const double sigma = scene.volume.rainExtinctionPerMeter;
  for (int y = 0; y < scene.camera.height; ++y) {
    const int x = scene.camera.width / 4;  // behind the wall
    const double expected =
        (1.0 -
         std::exp(-sigma * Eigen::Vector3d(scene.camera.rayCamera(x + 0.5, y + 0.5)).norm())) /
        (1.0 - std::exp(-sigma * 2000.0));
    const float o = open.pixel(x, y)[1], w = walled.pixel(x, y)[1];
    if (o > 1e-4f) {
      EXPECT_NEAR(w / o, expected, 1e-3 * expected + 1e-6) << y;
    }
    const int xr = 3 * scene.camera.width / 4;  // open sky on the right
    EXPECT_EQ(open.pixel(xr, y)[1], walled.pixel(xr, y)[1]);
  }
}

TEST(Rainbow, NoBowWhereTheGeometryHidesIt) {
  BowScene scene;
  const Camera& cam = scene.camera;
  EXPECT_EQ(rainbowHiddenReason(cam, scene.sun.direction), "");
  // The sun below the horizon: no light added, and a reason.
  scene.sun.direction = sunDirection(-5.0, 180.0);
  EXPECT_NE(rainbowHiddenReason(cam, scene.sun.direction), "");
  const Image below = scene.render();
  EXPECT_EQ(below.rgba, Image(cam.width, cam.height).rgba);
  // The sun in front of a narrow camera: the antisolar point is behind it, the bows outside.
  const Camera narrow = Camera::fromFieldOfView(400, 300, 30.0, 0.0, 1.6);
  EXPECT_NE(rainbowHiddenReason(narrow, sunDirection(10.0, 0.0)), "");
}

TEST(Rainbow, FiniteAtTheExtremes) {
  for (double elevation : {0.01, 45.0, 90.0})
    for (double rate : {0.1, 500.0}) {
      BowScene scene;
      scene.sun.direction = sunDirection(elevation, 180.0);
      scene.volume.rainExtinctionPerMeter = rain::rainExtinctionPerMeter(rate);
      scene.volume.fogExtinctionPerMeter = 0.05;
      std::vector<float> depth(size_t(scene.camera.width) * size_t(scene.camera.height), 0.0f);
      for (size_t i = 0; i < depth.size(); ++i)
        depth[i] = i % 3 == 0 ? std::numeric_limits<float>::infinity() : float(i % 50);
      const Image image = scene.render(&depth);
      for (float v : image.rgba)
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << elevation << " " << rate;
    }
}

TEST(Rainbow, SunFoundInTheTestEnvironment) {
  const std::optional<Sun> sun = findSun(lab::builtinTestEnvironment(256));
  ASSERT_TRUE(sun.has_value());
  // The built-in environment's sun stands 30 deg up.
  EXPECT_NEAR(std::asin(sun->direction.y()) / kDeg, 30.0, 1.5);
  EXPECT_GT(sun->irradianceRgb[0], 0.0);
  // A uniform sky has none.
  EXPECT_FALSE(findSun(uniformEquirect(64, 32, {1.0f, 1.0f, 1.0f})).has_value());
}

// At 1080p (cos(theta) looked up every 10 px and interpolated) every pixel's light against
// the single-scattering formula evaluated at that pixel's own angle: within 0.5 % of the bows'
// peak.
TEST(Rainbow, InterpolatedAnglesMatchEveryPixelsOwn) {
  BowScene scene;
  scene.camera = Camera::fromFieldOfView(1920, 1080, 50.0, -20.0, 1.6);
  scene.sun.direction = sunDirection(25.0, 180.0);
  const Image image = scene.render();
  const double sigma = scene.volume.rainExtinctionPerMeter;
  const double scattered = 0.5 * -std::expm1(-sigma * scene.volume.showerExtentMeters);
  double worst = 0.0, peak = 0.0;
  for (int y = 0; y < 1080; y += 3)
    for (int x = 0; x < 1920; x += 3)
      for (int c = 0; c < 3; ++c) {
        const double expected =
            3.0 * scene.profiles[size_t(c)].at(scene.scatteringDeg(x, y)) * scattered;
        worst = std::max(worst, std::abs(image.pixel(x, y)[c] - expected));
        peak = std::max(peak, expected);
      }
  ASSERT_GT(peak, 0.0);
  // Measured: 3.1e-4 of a 0.229 peak (0.13 %).
  EXPECT_LT(worst, 0.005 * peak) << "worst " << worst << " of " << peak;
}
