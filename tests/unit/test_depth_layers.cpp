#include <gtest/gtest.h>

#include <cmath>

#include "geometry/depth_layers.h"
#include "util/error.h"

using namespace pluvia;

TEST(DepthLayers, GroundPlaneDepthMatchesTheGeometry) {
  const double height = 2.0, tilt = 30.0;
  Camera camera = Camera::fromFieldOfView(100, 80, 60, tilt, height);
  auto depth = rasterizeDepthLayers(camera, nlohmann::json::parse(R"([{"type":"ground"}])"));
  // The pixel on the optical axis sees the ground at distance h / sin(tilt), z-depth the same.
  const float centre = depth[40 * 100 + 50];
  EXPECT_NEAR(centre, height / std::sin(tilt * M_PI / 180.0), 0.05);
  // Lower rows are nearer; above the horizon is sky.
  EXPECT_LT(depth[79 * 100 + 50], centre);
  Camera level = Camera::fromFieldOfView(100, 80, 60, 0.0, height);
  auto levelDepth = rasterizeDepthLayers(level, nlohmann::json::parse(R"([{"type":"ground"}])"));
  EXPECT_TRUE(std::isinf(levelDepth[10 * 100 + 50]));
  // Level camera, row y: z-depth = h * f / (y + 0.5 - cy).
  const int y = 70;
  EXPECT_NEAR(levelDepth[y * 100 + 50], height * level.focalPx / (y + 0.5 - level.cy), 1e-3);
}

TEST(DepthLayers, CardsAndSkyPaintInOrder) {
  Camera camera = Camera::fromFieldOfView(10, 10, 60, 0.0, 1.6);
  auto depth = rasterizeDepthLayers(camera, nlohmann::json::parse(R"([
      {"type":"ground"},
      {"type":"card","distance_m":7,"x0":0,"x1":0.5,"y0":0,"y1":1},
      {"type":"sky","x0":0,"x1":1,"y0":0,"y1":0.2}])"));
  EXPECT_FLOAT_EQ(depth[5 * 10 + 2], 7.0f);
  EXPECT_TRUE(std::isinf(depth[1 * 10 + 2]));  // sky painted over the card
  EXPECT_TRUE(std::isfinite(depth[9 * 10 + 8]));  // ground
  EXPECT_THROW(rasterizeDepthLayers(camera, nlohmann::json::parse(R"([{"type":"wall"}])")), Error);
}
