// Splatter flashes (rain/splatter.h): drawn only at impact sites, on the surface that took the
// impact and never over what stands in front of it, for exactly the stated flash (the exposure
// share it overlaps), sized by the drop's diameter, the same every time.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geometry/camera.h"
#include "image/image.h"
#include "rain/drop_physics.h"
#include "rain/splash_rate.h"
#include "rain/splashes.h"
#include "rain/splatter.h"

using namespace pluvia;
using namespace pluvia::rain;

namespace {

constexpr double kFlash = 0.04;

// z-depth of the ground y = 0 (+inf above the horizon), with a post 1 m away over columns
// 90..109 that faces the camera and hides the ground behind it.
std::vector<float> groundWithPost(const Camera& camera) {
  std::vector<float> depth(size_t(camera.width) * size_t(camera.height));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      double t = ray.y() < 0.0 ? -camera.positionMeters.y() / ray.y()
                               : std::numeric_limits<double>::infinity();
      if (x >= 90 && x < 110) t = 1.0;
      depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(t);
    }
  return depth;
}

std::vector<float> draw(const Camera& camera, const std::vector<float>& depth,
                        const std::vector<Impact>& impacts, double open, double close) {
  std::vector<ShadedImpact> shaded;
  for (const Impact& i : impacts) shaded.push_back({&i, {1.0f, 1.0f, 1.0f}});
  Image image(camera.width, camera.height);
  std::vector<float> alpha(image.pixelCount(), 0.0f);
  drawSplatters(image, alpha, depth, camera, shaded, kFlash, open, close, 1.0f);
  return alpha;
}

double sum(const std::vector<float>& v) {
  double s = 0.0;
  for (float x : v) s += x;
  return s;
}

}  // namespace

TEST(Splatter, OnlyAtImpactSitesOnTheSurfaceThatTookThem) {
  const Camera camera = Camera::fromFieldOfView(200, 150, 50.0, 40.0, 1.6);
  const std::vector<float> depth = groundWithPost(camera);
  const double rate = 100.0, fps = 24.0;
  const SplashField field{depth, upFacingAreaPerPixel(camera, depth, 30.0),
                          impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer,
                                                      VelocityModel::Atlas, rate, 0.5, 6.0)};
  const ImpactDiameters diameters(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate, 0.5,
                                  6.0);
  std::vector<Impact> impacts =
      impactsBorn(field, camera, 3, fps, 7, diameters, VelocityModel::Atlas);
  ASSERT_GT(impacts.size(), 20u);
  // One more on the ground just behind the post's left edge: its texture reaches behind the
  // post, which hides that part.
  Impact behind = impacts.front();
  {
    const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(90.5, 120.5);
    behind.point = camera.positionMeters + ray * (-camera.positionMeters.y() / ray.y());
    behind.diameterMm = 5.0;
    impacts.push_back(behind);
  }
  const double open = 3.0 / fps, close = open + 0.02;
  std::vector<Impact> flashing;  // those the shutter sees, all of them made at frame 3
  for (const Impact& i : impacts)
    if (splatterExposureShare(i.timeSeconds, kFlash, open, close) > 0.0) flashing.push_back(i);
  const std::vector<float> alpha = draw(camera, depth, flashing, open, close);
  EXPECT_GT(sum(alpha), 1.0);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float a = alpha[size_t(y) * 200 + size_t(x)];
      ASSERT_TRUE(std::isfinite(a) && a >= 0.0f && a <= 1.0f);
      if (a == 0.0f) continue;
      EXPECT_FALSE(x >= 90 && x < 110) << "splatter on the post at " << x << "," << y;
      // Within a texture's reach (and the pixel's rim) of an impact seen by the shutter.
      double nearest = std::numeric_limits<double>::infinity();
      for (const Impact& i : flashing) {
        double px, py, z;
        ASSERT_TRUE(camera.project(i.point, px, py, z));
        const double reach = camera.focalPx * kSplatterReachPerDiameter * i.diameterMm * 1e-3 / z;
        nearest = std::min(nearest, std::hypot(x + 0.5 - px, y + 0.5 - py) - reach);
      }
      EXPECT_LT(nearest, 1.5) << "splatter away from every impact at " << x << "," << y;
    }
  // The one behind the post shows left of it only.
  const std::vector<float> alone =
      draw(camera, depth, {behind}, behind.timeSeconds, behind.timeSeconds + 0.02);
  double left = 0.0;
  for (int y = 100; y < 140; ++y)
    for (int x = 80; x < 90; ++x) left += alone[size_t(y) * 200 + size_t(x)];
  EXPECT_GT(left, 0.5);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 90; x < 110; ++x) ASSERT_EQ(alone[size_t(y) * 200 + size_t(x)], 0.0f);
}

TEST(Splatter, LastsTheStatedFlashWithItsExposureShare) {
  const Camera camera = Camera::fromFieldOfView(200, 150, 50.0, 40.0, 1.6);
  const std::vector<float> depth = groundWithPost(camera);
  Impact impact;
  const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(50.5, 120.5);
  impact.point = camera.positionMeters + ray * (-camera.positionMeters.y() / ray.y());
  impact.timeSeconds = 1.0;
  impact.diameterMm = 4.0;
  impact.speedMetersPerSecond = 8.8;
  impact.key = 12345;
  const double t = impact.timeSeconds, exposure = 0.02;
  auto seen = [&](double open) {
    return sum(draw(camera, depth, {impact}, open, open + exposure));
  };
  const double whole = seen(t + 0.01);  // the shutter inside the flash
  EXPECT_GT(whole, 1.0);
  EXPECT_EQ(seen(t - exposure - 1e-4), 0.0);  // closed before the impact
  EXPECT_EQ(seen(t + kFlash + 1e-4), 0.0);    // opened after the flash
  EXPECT_NEAR(seen(t + kFlash - 0.5 * exposure), 0.5 * whole, 1e-4 * whole);  // half of it
  EXPECT_NEAR(seen(t - 0.5 * exposure), 0.5 * whole, 1e-4 * whole);
  EXPECT_EQ(seen(t + 0.01), whole);  // the same every time
  EXPECT_DOUBLE_EQ(splatterExposureShare(t, kFlash, t + 0.01, t + 0.03), 1.0);
  EXPECT_DOUBLE_EQ(splatterExposureShare(t, kFlash, t + 0.03, t + 0.05), 0.5);
}

TEST(Splatter, TextureSizedByTheDropAndBoundedByItsReach) {
  Impact small, big;
  small.diameterMm = 2.0, big.diameterMm = 4.0;
  small.key = big.key = 99;  // the same shape
  const double step = 0.1e-3;
  double areaSmall = 0.0, areaBig = 0.0;
  for (double u = -0.02; u <= 0.02; u += step)
    for (double v = -0.02; v <= 0.02; v += step) {
      const double r = std::hypot(u, v);
      const double os = splatterOpacity(small, u, v, 1e-6), ob = splatterOpacity(big, u, v, 1e-6);
      ASSERT_LE(os, kSplatterPeakOpacity);
      if (r > kSplatterReachPerDiameter * 2e-3) {
        ASSERT_EQ(os, 0.0) << u << " " << v;
      }
      if (r > kSplatterReachPerDiameter * 4e-3) {
        ASSERT_EQ(ob, 0.0) << u << " " << v;
      }
      areaSmall += os > 0.0, areaBig += ob > 0.0;
    }
  EXPECT_DOUBLE_EQ(splatterOpacity(small, 0.0, 0.0, 1e-6), kSplatterPeakOpacity);
  EXPECT_NEAR(areaBig / areaSmall, 4.0, 0.1);  // twice the diameter, four times the area
}
