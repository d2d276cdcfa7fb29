#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "geometry/camera_path.h"
#include "geometry/depth_layers.h"
#include "preset/ramp.h"
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
  EXPECT_TRUE(std::isinf(depth[1 * 10 + 2]));     // sky painted over the card
  EXPECT_TRUE(std::isfinite(depth[9 * 10 + 8]));  // ground
  EXPECT_THROW(rasterizeDepthLayers(camera, nlohmann::json::parse(R"([{"type":"wall"}])")), Error);
}

namespace {
using nlohmann::json;

const KeyedNumberAt kRampAt = [](const json& v, double frame) {
  return Ramp::fromJson(v).valueAt(frame);
};

// Edge-function test at a pixel centre, independent of the scanline fill (no centre below lies
// on an edge).
bool insideTriangle(const std::array<double, 2>& a, const std::array<double, 2>& b,
                    const std::array<double, 2>& c, double x, double y) {
  auto side = [&](const std::array<double, 2>& p, const std::array<double, 2>& q) {
    return (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
  };
  const double ab = side(a, b), bc = side(b, c), ca = side(c, a);
  return (ab > 0 && bc > 0 && ca > 0) || (ab < 0 && bc < 0 && ca < 0);
}
}  // namespace

TEST(DepthLayers, PolygonCoversExactlyThePixelCentresInside) {
  Camera camera = Camera::fromFieldOfView(20, 20, 60, 0.0, 1.6);
  auto depth = rasterizeDepthLayers(camera, json::parse(R"([
      {"type":"polygon","points":[[0.1,0.1],[0.9,0.15],[0.3,0.85]],"depth_m":7}])"));
  const std::array<double, 2> a{2, 2}, b{18, 3}, c{6, 17};  // the points in pixels
  int covered = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const float d = depth[y * 20 + x];
      if (insideTriangle(a, b, c, x + 0.5, y + 0.5)) {
        EXPECT_FLOAT_EQ(d, 7.0f) << x << "," << y;
        ++covered;
      } else {
        EXPECT_TRUE(std::isinf(d)) << x << "," << y;
      }
    }
  }
  // Area 0.5 * |(b - a) x (c - a)| = 0.5 * |16 * 15 - 1 * 4| = 118 pixels, to within the edges.
  EXPECT_NEAR(covered, 118, 12);

  // An axis-aligned quad from pixel 2 to 6 (x) and 3 to 7 (y): 4 x 4 centres, in any winding.
  Camera small = Camera::fromFieldOfView(10, 10, 60, 0.0, 1.6);
  auto quad = rasterizeDepthLayers(small, json::parse(R"([
      {"type":"polygon","points":[[0.2,0.3],[0.2,0.7],[0.6,0.7],[0.6,0.3]],"depth_m":3}])"));
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      EXPECT_EQ(quad[y * 10 + x] == 3.0f, x >= 2 && x < 6 && y >= 3 && y < 7) << x << "," << y;

  // Even-odd: a self-overlapping star (pentagram) leaves its centre pentagon empty.
  Camera square = Camera::fromFieldOfView(101, 101, 60, 0.0, 1.6);
  json star = json::array();
  for (int k = 0; k < 5; ++k) {
    const double angle = M_PI / 2 + k * 2 * (2 * M_PI / 5);
    star.push_back({0.5 + 0.45 * std::cos(angle), 0.5 - 0.45 * std::sin(angle)});
  }
  auto starDepth = rasterizeDepthLayers(
      square, json::array({json{{"type", "polygon"}, {"points", star}, {"depth_m", 5}}}));
  EXPECT_TRUE(std::isinf(starDepth[50 * 101 + 50]));  // the centre: crossed twice
  EXPECT_FLOAT_EQ(starDepth[10 * 101 + 50], 5.0f);    // the top spike
}

TEST(DepthLayers, RampedPolygonGoesFromTopDepthToBottomDepth) {
  Camera camera = Camera::fromFieldOfView(10, 20, 60, 0.0, 1.6);
  auto depth = rasterizeDepthLayers(camera, json::parse(R"([
      {"type":"polygon","points":[[0,0.5],[1,0.5],[1,1],[0,1]],"depth_m":20,"depth_bottom_m":4}])"));
  // Top at pixel row 10, bottom at 20: row y's centre is (y + 0.5 - 10) / 10 of the way down.
  EXPECT_TRUE(std::isinf(depth[9 * 10 + 5]));
  EXPECT_NEAR(depth[10 * 10 + 5], 20 - 0.05 * 16, 1e-4);
  EXPECT_NEAR(depth[15 * 10 + 0], 20 - 0.55 * 16, 1e-4);
  EXPECT_NEAR(depth[19 * 10 + 9], 20 - 0.95 * 16, 1e-4);
}

TEST(DepthLayers, PolygonsPaintInListOrderAndSkyTakesPoints) {
  Camera camera = Camera::fromFieldOfView(10, 10, 60, 0.0, 1.6);
  auto depth = rasterizeDepthLayers(camera, json::parse(R"([
      {"type":"card","distance_m":9},
      {"type":"polygon","points":[[0,0],[0.5,0],[0.5,1],[0,1]],"depth_m":4},
      {"type":"card","distance_m":6,"x0":0,"x1":1,"y0":0.8,"y1":1},
      {"type":"sky","points":[[0.6,0],[1,0],[1,0.4]]}])"));
  EXPECT_FLOAT_EQ(depth[5 * 10 + 2], 4.0f);    // polygon over the first card
  EXPECT_FLOAT_EQ(depth[5 * 10 + 7], 9.0f);    // the first card alone
  EXPECT_FLOAT_EQ(depth[9 * 10 + 2], 6.0f);    // the second card over the polygon
  EXPECT_TRUE(std::isinf(depth[0 * 10 + 9]));  // the sky triangle's corner
  EXPECT_FLOAT_EQ(depth[3 * 10 + 6], 9.0f);    // below its diagonal: not sky
  // A sky with points ignores its (default, full-frame) rectangle.
  auto skyOnly = rasterizeDepthLayers(camera, json::parse(R"([
      {"type":"card","distance_m":9},
      {"type":"sky","x0":0,"x1":1,"y0":0,"y1":1,"points":[[0,0],[0.3,0],[0,0.3]]}])"));
  EXPECT_TRUE(std::isinf(skyOnly[0]));
  EXPECT_FLOAT_EQ(skyOnly[9 * 10 + 9], 9.0f);
  EXPECT_THROW(
      rasterizeDepthLayers(camera, json::parse(R"([{"type":"polygon","points":[[0,0],[1,1]]}])")),
      Error);
}

TEST(DepthLayers, KeyframedFieldsAreEvaluatedAtTheFrame) {
  Camera camera = Camera::fromFieldOfView(10, 10, 60, 0.0, 1.6);
  json layers = json::parse(R"([
      {"type":"card","distance_m":{"keys":[[10,5],[20,15]],"interpolation":"linear"},
       "x0":0,"x1":[[10,0.5],[20,1]],"y0":0,"y1":1},
      {"type":"polygon","points":[[0,0.8],[1,0.8],[1,1],[0,1]],
       "depth_m":{"keys":[[0,2],[10,4]],"interpolation":"hold"}}])");
  EXPECT_TRUE(depthLayersAnimated(layers));
  auto at = [&](double frame) { return rasterizeDepthLayers(camera, layers, frame, kRampAt); };
  auto before = at(0), between = at(15), after = at(30);
  EXPECT_FLOAT_EQ(before[2 * 10 + 2], 5.0f);  // before the first key: the first value
  EXPECT_FLOAT_EQ(between[2 * 10 + 2], 10.0f);
  EXPECT_FLOAT_EQ(after[2 * 10 + 2], 15.0f);  // after the last key: the last value
  // x1 goes from half the width to the full width: pixel 6 is covered only later.
  EXPECT_TRUE(std::isinf(before[2 * 10 + 6]));
  EXPECT_FLOAT_EQ(between[2 * 10 + 6], 10.0f);  // x1 = 0.75 at frame 15
  EXPECT_TRUE(std::isinf(between[2 * 10 + 8]));
  // Hold: 2 until frame 10, then 4.
  EXPECT_FLOAT_EQ(at(9.5)[9 * 10 + 5], 2.0f);
  EXPECT_FLOAT_EQ(at(10)[9 * 10 + 5], 4.0f);
  // Keys without a reader are refused, naming the layer.
  try {
    rasterizeDepthLayers(camera, layers, 0.0);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("depth layer 0"), std::string::npos) << e.what();
  }
}

TEST(DepthLayers, KeyframedPointsMoveLinearly) {
  Camera camera = Camera::fromFieldOfView(20, 10, 60, 0.0, 1.6);
  json layers = json::parse(R"([{"type":"polygon","depth_m":3,"points":[
      {"frame":0,"points":[[0,0],[0.2,0],[0.2,1],[0,1]]},
      {"frame":10,"points":[[0.5,0],[0.7,0],[0.7,1],[0.5,1]]}]}])");
  EXPECT_TRUE(depthLayersAnimated(layers));
  auto at5 = rasterizeDepthLayers(camera, layers, 5, kRampAt);  // x from 0.25 to 0.45: px 5-9
  for (int x = 0; x < 20; ++x) EXPECT_EQ(at5[4 * 20 + x] == 3.0f, x >= 5 && x < 9) << x;
  auto at20 = rasterizeDepthLayers(camera, layers, 20, kRampAt);  // held at the last key
  for (int x = 0; x < 20; ++x) EXPECT_EQ(at20[4 * 20 + x] == 3.0f, x >= 10 && x < 14) << x;
}

TEST(DepthLayers, AnimatedOnlyWhenSomethingChanges) {
  EXPECT_FALSE(depthLayersAnimated(json::parse(R"([{"type":"ground"},
      {"type":"card","distance_m":4,"x0":0.1},
      {"type":"polygon","points":[[0,0],[1,0],[1,1]],"depth_m":{"keys":[[0,3],[9,3]]}},
      {"type":"sky","points":[{"frame":0,"points":[[0,0],[1,0],[1,1]]}]}])")));
  EXPECT_TRUE(depthLayersAnimated(json::parse(R"([{"type":"card","y1":[[0,0.2],[9,0.3]]}])")));
}

TEST(DepthLayers, GroundFollowsAMovingCamera) {
  Camera base = Camera::fromFieldOfView(64, 48, 60, 0.0, 1.6);
  CameraPose start, end;
  start.positionMeters = {0, 2, 0};
  start.pitchDeg = -30;
  end.positionMeters = {3, 4, -5};
  end.pitchDeg = -30;
  end.yawDeg = 40;
  CameraPath path = CameraPath::fromKeys(base, {{0.0, start}, {10.0, end}});
  const Camera camera = path.cameraAt(5);  // height 3, still 30 degrees down
  auto depth = rasterizeDepthLayers(camera, json::parse(R"([{"type":"ground"}])"), 5, kRampAt);
  // Pixel (32, 24) is half a pixel below and right of the optical axis: its ray (z = -1) drops by
  // sin(tilt) + cos(tilt) * 0.5 / f per unit of z-depth (yaw and x do not change that).
  const double tilt = 30 * M_PI / 180;
  const double drop = std::sin(tilt) + std::cos(tilt) * 0.5 / camera.focalPx;
  EXPECT_NEAR(depth[24 * 64 + 32], 3.0 / drop, 1e-4);
  // Elsewhere: intersect the pixel's ray with y = 0 and project the hit point back (project()
  // gives its z-depth independently of the rasteriser's formula).
  for (auto [x, y] : {std::pair{5, 40}, std::pair{60, 30}, std::pair{32, 47}}) {
    const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
    ASSERT_LT(ray.y(), 0);
    const Eigen::Vector3d hit =
        camera.positionMeters + ray * (camera.positionMeters.y() / -ray.y());
    EXPECT_NEAR(hit.y(), 0.0, 1e-9);
    double px, py, zDepth;
    ASSERT_TRUE(camera.project(hit, px, py, zDepth));
    EXPECT_NEAR(px, x + 0.5, 1e-6);
    EXPECT_NEAR(depth[y * 64 + x], zDepth, 1e-4 * zDepth) << x << "," << y;
  }
  // The first frame's camera is lower: the same pixel sees nearer ground.
  auto first = rasterizeDepthLayers(path.cameraAt(0), json::parse(R"([{"type":"ground"}])"));
  EXPECT_NEAR(first[24 * 64 + 32], 2.0 / drop, 1e-4);
}
