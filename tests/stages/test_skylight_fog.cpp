// The skylight fog over a frame (stages/skylight_fog.h): the sky keeps its values, no medium
// changes nothing, a surface fades toward the table's in-scattering by 1 - exp(-sigma d), and
// the in-scattering interpolated between nodes stays within 2e-3 of a lookup at every pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/camera.h"
#include "lab/test_environment.h"
#include "optics/skylight_scattering.h"
#include "stages/skylight_fog.h"

namespace pluvia {
namespace {

Image plate(int w, int h, float depthMeters) {
  Image image(w, h);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + size_t(c)] = 0.1f * float(c + 1);
  std::vector<float>& depth = image.plane("depth");
  for (size_t i = 0; i < depth.size(); ++i)
    depth[i] = i < depth.size() / 2 ? std::numeric_limits<float>::infinity() : depthMeters;
  return image;
}

TEST(SkylightFog, SkyUntouchedSurfaceFadesTowardInscatter) {
  const Camera camera = Camera::fromFieldOfView(32, 16, 60.0, 0.0, 1.5);
  const optics::SkylightTable table =
      optics::buildSkylightTable(optics::cieOvercastSky(64, {1, 1, 1}), 16);
  optics::SkylightMedium medium;
  medium.rainExtinctionPerMeter = 4e-3;
  medium.fogPerMeter = 2e-3;
  const Image before = plate(32, 16, 200.0f);
  Image image = before;
  applySkylightFog(image, camera, table, medium, std::numeric_limits<double>::infinity());
  const double sigma = medium.extinctionPerMeter();
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 32; ++x) {
      const size_t i = size_t(y) * 32 + size_t(x);
      if (i < image.pixelCount() / 2) {  // sky rows: bit for bit
        for (int c = 0; c < 4; ++c) EXPECT_EQ(image.rgba[i * 4 + c], before.rgba[i * 4 + c]);
        continue;
      }
      const Eigen::Vector3d ray = camera.rayCamera(x + 0.5, y + 0.5);
      const Eigen::Vector3d view = (camera.worldFromCamera * ray).normalized();
      const double alpha = 1.0 - std::exp(-sigma * 200.0 * ray.norm());
      const auto in = optics::skylightInscatter(table, medium, {view.x(), view.y(), view.z()});
      for (int c = 0; c < 3; ++c) {
        const double expected = alpha * in[size_t(c)] + (1 - alpha) * before.rgba[i * 4 + c];
        EXPECT_NEAR(image.rgba[i * 4 + c], expected, 1e-5);
      }
    }
  }
}

TEST(SkylightFog, NoMediumChangesNothingAndExtremesStayFinite) {
  const Camera camera = Camera::fromFieldOfView(16, 8, 60.0, 10.0, 1.5);
  const optics::SkylightTable table =
      optics::buildSkylightTable(optics::cieOvercastSky(64, {1, 1, 1}), 16);
  const Image before = plate(16, 8, 50.0f);
  Image image = before;
  applySkylightFog(image, camera, table, optics::SkylightMedium{}, 1e9);
  EXPECT_EQ(image.rgba, before.rgba);
  optics::SkylightMedium dense;
  dense.fogPerMeter = 1e6;
  Image far = plate(16, 8, 1e30f);
  applySkylightFog(far, camera, table, dense, std::numeric_limits<double>::infinity());
  for (float v : far.rgba) EXPECT_TRUE(std::isfinite(v));
}

// A 1080p-like lens (0.1 deg per pixel) over an environment with a sun and a bright sky: the
// airlight interpolated between nodes against the table looked up at every pixel.
TEST(SkylightFog, NodesWithinTwoThousandthsOfEveryPixelsLookup) {
  const Camera camera = Camera::fromFieldOfView(480, 270, 50.0, 20.0, 1.5);
  const optics::SkylightTable table =
      optics::buildSkylightTable(lab::builtinTestEnvironment(256), 64);
  ASSERT_GT(skylightNodeStepPx(camera, table), 4);  // the nodes are sparser than the pixels
  optics::SkylightMedium medium;
  medium.rainExtinctionPerMeter = 4e-3;
  medium.fogPerMeter = 1e-3;
  // Black surfaces so far away that what is left is the airlight alone.
  Image image(camera.width, camera.height);
  std::vector<float>& depth = image.plane("depth");
  std::fill(depth.begin(), depth.end(), 1e6f);
  applySkylightFog(image, camera, table, medium, std::numeric_limits<double>::infinity());
  double worst = 0.0, brightest = 0.0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d view =
          (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
      const auto in = optics::skylightInscatter(table, medium, {view.x(), view.y(), view.z()});
      for (int c = 0; c < 3; ++c) {
        const float got = image.pixel(x, y)[c];
        ASSERT_TRUE(std::isfinite(got));
        worst = std::max(worst, std::abs(double(got) - in[size_t(c)]));
        brightest = std::max(brightest, double(in[size_t(c)]));
      }
    }
  // Measured: 1.5e-3 of 1.28 at a node step of 6 px.
  EXPECT_LT(worst, 2e-3 * brightest) << "worst " << worst << " of " << brightest;
}

}  // namespace
}  // namespace pluvia
