// SyntheticSceneRenderer against analytic answers: z-depth on the ground (ray-plane), on the
// back wall (its distance), everywhere against a CPU ray caster of the same boxes, the sky
// (+infinity and its colour), silhouettes of a box at its projected edges, determinism,
// texture contrast and matchable features, and the default path's pose convention.
//
// Set PLUVIA_SYNTHETIC_SCENE_PNG_DIR to a folder to get frames 0, 23 and 47 of the default path
// as sRGB PNGs there (for looking at them).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/features2d.hpp>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "image/image.h"
#include "lab/synthetic_scene.h"
#include "test_support.h"
#include "util/error.h"

namespace pluvia::lab {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 180;
constexpr double kDepthRelTolerance = 0.005;  // 0.5 %
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One context for the whole suite: creating one costs more than the renders here.
class SyntheticSceneTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { renderer_ = new SyntheticSceneRenderer(kWidth, kHeight); }
  static void TearDownTestSuite() {
    delete renderer_;
    renderer_ = nullptr;
  }
  SyntheticSceneRenderer& renderer() { return *renderer_; }

  // The default intrinsics as a pluvia Camera at 1.6 m, level, looking down the corridor.
  static Camera levelCamera() {
    Camera camera = defaultSyntheticIntrinsics(kWidth, kHeight).toCamera<Camera>();
    camera.positionMeters = Eigen::Vector3d(0.0, kSyntheticCameraHeightMeters, 0.0);
    return camera;
  }

  static SyntheticSceneRenderer* renderer_;
};
SyntheticSceneRenderer* SyntheticSceneTest::renderer_ = nullptr;

float depthAt(const Image& image, int x, int y) {
  return (*image.findPlane("depth"))[static_cast<size_t>(y) * image.width + x];
}

// Ray parameter t > 0 of the nearest hit of origin + t * dir with the scene (+inf for none).
// With the ray scaled to camera z = -1, t is the z-depth itself.
double castRay(const SyntheticScene& scene, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& dir) {
  double best = kInfinity;
  const double w = scene.halfWidthMeters;
  const double h = scene.wallHeightMeters;
  auto inside = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  auto consider = [&](int axis, double plane, auto&& within) {
    if (dir[axis] == 0.0) return;
    const double t = (plane - origin[axis]) / dir[axis];
    if (t <= 0.0 || t >= best) return;
    const Eigen::Vector3d p = origin + t * dir;
    if (within(p)) best = t;
  };
  const double zLo = scene.backWallZMeters;
  const double zHi = scene.openEndZMeters;
  consider(1, 0.0, [&](const Eigen::Vector3d& p) {
    return inside(p.x(), -w, w) && inside(p.z(), zLo, zHi);
  });
  for (double x : {-w, w}) {
    consider(0, x, [&](const Eigen::Vector3d& p) {
      return inside(p.y(), 0.0, h) && inside(p.z(), zLo, zHi);
    });
  }
  consider(2, zLo,
           [&](const Eigen::Vector3d& p) { return inside(p.x(), -w, w) && inside(p.y(), 0.0, h); });
  for (const SyntheticBox& box : scene.boxes) {
    const Eigen::Vector3d lo(box.centerXMeters - 0.5 * box.sizeXMeters, 0.0,
                             box.centerZMeters - 0.5 * box.sizeZMeters);
    const Eigen::Vector3d hi(box.centerXMeters + 0.5 * box.sizeXMeters, box.heightMeters,
                             box.centerZMeters + 0.5 * box.sizeZMeters);
    for (int axis = 0; axis < 3; ++axis) {
      for (double plane : {lo[axis], hi[axis]}) {
        consider(axis, plane, [&](const Eigen::Vector3d& p) {
          for (int other = 0; other < 3; ++other) {
            if (other != axis && !inside(p[other], lo[other], hi[other])) return false;
          }
          return true;
        });
      }
    }
  }
  return best;
}

std::vector<double> analyticDepth(const SyntheticScene& scene, const Camera& camera) {
  std::vector<double> depth(static_cast<size_t>(camera.width) * camera.height);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      depth[static_cast<size_t>(y) * camera.width + x] = castRay(scene, camera.positionMeters, ray);
    }
  }
  return depth;
}

TEST_F(SyntheticSceneTest, GroundDepthIsTheRayPlaneDistance) {
  // Pitched down as on the default path, so most of the lower half is ground.
  Camera camera = levelCamera();
  camera.worldFromCamera =
      Eigen::AngleAxisd(-3.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Image image = renderer().render(camera);
  const double height = camera.positionMeters.y();
  // Bottom rows, centre columns: in front of every box (the nearest stands 7.25 m away).
  int checked = 0;
  for (int y = kHeight - 30; y < kHeight; y += 5) {
    for (int x = kWidth / 2 - 40; x <= kWidth / 2 + 40; x += 10) {
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      ASSERT_LT(ray.y(), 0.0);
      const double expected = height / -ray.y();  // as in geometry/depth_layers.cpp
      EXPECT_NEAR(depthAt(image, x, y), expected, kDepthRelTolerance * expected)
          << "pixel " << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
}

TEST_F(SyntheticSceneTest, BackWallDepthIsItsDistance) {
  const Camera camera = levelCamera();
  const Image image = renderer().render(camera);
  const double wallDistance = -renderer().scene().backWallZMeters;
  // The image centre looks straight down the corridor, between the pillar and the tall block.
  EXPECT_NEAR(depthAt(image, kWidth / 2, kHeight / 2), wallDistance,
              kDepthRelTolerance * wallDistance);
  // And every pixel whose ray meets the back wall first (by the CPU ray caster) reads the
  // wall's distance, whatever its angle: z-depth, not ray length.
  const std::vector<double> expected = analyticDepth(renderer().scene(), camera);
  int wallPixels = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    if (std::abs(expected[i] - wallDistance) > 1e-9) continue;
    ++wallPixels;
    ASSERT_NEAR((*image.findPlane("depth"))[i], wallDistance, kDepthRelTolerance * wallDistance)
        << "pixel " << i % kWidth << "," << i / kWidth;
  }
  EXPECT_GT(wallPixels, 1000);
}

TEST_F(SyntheticSceneTest, DepthMatchesRayCasterAwayFromEdges) {
  // A pose off the axes (the last frame of the default path): walls, boxes, ground and sky.
  const SyntheticView intrinsics = defaultSyntheticIntrinsics(kWidth, kHeight);
  const std::vector<SyntheticPathKey> path = defaultSyntheticPath();
  const SyntheticView view = syntheticViewAt(intrinsics, path.back());
  const Image image = renderer().render(view);
  Camera camera = levelCamera();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) camera.worldFromCamera(r, c) = view.worldFromCamera[r * 3 + c];
  }
  camera.positionMeters =
      Eigen::Vector3d(view.positionMeters[0], view.positionMeters[1], view.positionMeters[2]);
  const std::vector<double> expected = analyticDepth(renderer().scene(), camera);
  const std::vector<float>& depth = *image.findPlane("depth");
  int compared = 0;
  int sky = 0;
  for (int y = 1; y < kHeight - 1; ++y) {
    for (int x = 1; x < kWidth - 1; ++x) {
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      // Skip pixels next to a silhouette: there a sub-pixel difference in coverage flips the
      // surface, which the silhouette test checks separately.
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const double n = expected[i + dy * kWidth + dx];
          if (std::isinf(n) != std::isinf(expected[i]) ||
              std::abs(n - expected[i]) > 0.05 * expected[i]) {
            edge = true;
          }
        }
      }
      if (edge) continue;
      ++compared;
      if (std::isinf(expected[i])) {
        ++sky;
        ASSERT_TRUE(std::isinf(depth[i]) && depth[i] > 0) << "pixel " << x << "," << y;
      } else {
        ASSERT_NEAR(depth[i], expected[i], kDepthRelTolerance * expected[i])
            << "pixel " << x << "," << y;
      }
    }
  }
  EXPECT_GT(compared, kWidth * kHeight * 8 / 10);
  EXPECT_GT(sky, 100);
}

TEST_F(SyntheticSceneTest, SkyIsInfinitelyFarAndSkyColoured) {
  const Camera camera = levelCamera();
  const Image image = renderer().render(camera);
  // Top rows over the centre: 18 degrees up, over the 8 m back wall (14 m high there).
  for (int y = 0; y < 5; ++y) {
    for (int x = kWidth / 2 - 30; x <= kWidth / 2 + 30; x += 5) {
      const float depth = depthAt(image, x, y);
      EXPECT_TRUE(std::isinf(depth) && depth > 0) << "pixel " << x << "," << y << ": " << depth;
      const Eigen::Vector3d ray =
          (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
      const std::array<float, 3> sky = syntheticSkyRgb(ray.y());
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(image.pixel(x, y)[c], sky[c], 1e-3) << "pixel " << x << "," << y;
      }
      EXPECT_EQ(image.pixel(x, y)[3], 1.0f);
    }
  }
}

TEST_F(SyntheticSceneTest, BoxSilhouetteLandsWhereTheEdgeProjects) {
  const Camera camera = levelCamera();
  const Image image = renderer().render(camera);
  // The tall block on the right (x 1.6..3.6, z -15..-13, 2.5 m tall) against the back wall.
  const SyntheticBox& box = renderer().scene().boxes.at(1);
  const double x0 = box.centerXMeters - 0.5 * box.sizeXMeters;
  const double zFar = box.centerZMeters - 0.5 * box.sizeZMeters;
  const double zNear = box.centerZMeters + 0.5 * box.sizeZMeters;
  const double boxFarthest = -zFar + 0.01;
  double px = 0.0, py = 0.0, depth = 0.0;

  // Left silhouette: the far left vertical edge (the box's left face is in view from x = 0).
  ASSERT_TRUE(camera.project({x0, 0.5 * box.heightMeters, zFar}, px, py, depth));
  const int row = static_cast<int>(py);
  int firstCovered = -1;
  for (int x = 0; x < kWidth; ++x) {
    if (depthAt(image, x, row) <= boxFarthest && x > kWidth / 2) {
      firstCovered = x;
      break;
    }
  }
  ASSERT_GE(firstCovered, 0);
  EXPECT_NEAR(firstCovered + 0.5, px, 1.0);

  // Top silhouette: the near top edge (the top face is above the 1.6 m eye, out of view).
  ASSERT_TRUE(camera.project({box.centerXMeters, box.heightMeters, zNear}, px, py, depth));
  const int column = static_cast<int>(px);
  int topCovered = -1;
  for (int y = 0; y < kHeight; ++y) {
    if (depthAt(image, column, y) <= boxFarthest) {
      topCovered = y;
      break;
    }
  }
  ASSERT_GE(topCovered, 0);
  EXPECT_NEAR(topCovered + 0.5, py, 1.0);

  // The corner where the two meet: top of the far left edge.
  ASSERT_TRUE(camera.project({x0, box.heightMeters, zFar}, px, py, depth));
  const int cx = static_cast<int>(std::floor(px + 1.0));
  const int cy = static_cast<int>(std::floor(py + 1.0));
  EXPECT_LE(depthAt(image, cx, cy), boxFarthest);      // inside, down-right
  EXPECT_GT(depthAt(image, cx - 2, cy), boxFarthest);  // left of it
  EXPECT_GT(depthAt(image, cx, cy - 2), boxFarthest);  // above it
}

TEST_F(SyntheticSceneTest, RendersAreByteIdentical) {
  const SyntheticView view =
      syntheticViewAt(defaultSyntheticIntrinsics(kWidth, kHeight), defaultSyntheticPath()[10]);
  const Image a = renderer().render(view);
  const Image b = renderer().render(view);
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  EXPECT_EQ(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)), 0);
  const std::vector<float>& da = *a.findPlane("depth");
  const std::vector<float>& db = *b.findPlane("depth");
  EXPECT_EQ(std::memcmp(da.data(), db.data(), da.size() * sizeof(float)), 0);
}

double luminanceStdDev(const Image& image, int x0, int y0, int size) {
  double sum = 0.0, sumSq = 0.0;
  for (int y = y0; y < y0 + size; ++y) {
    for (int x = x0; x < x0 + size; ++x) {
      const float* p = image.pixel(x, y);
      const double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      sum += lum;
      sumSq += lum * lum;
    }
  }
  const double n = static_cast<double>(size) * size;
  return std::sqrt(std::max(sumSq / n - (sum / n) * (sum / n), 0.0));
}

TEST_F(SyntheticSceneTest, SurfacesAreTexturedAndLitDifferently) {
  const Camera camera = levelCamera();
  const Image image = renderer().render(camera);
  // Left wall (rows around the horizon at the left edge), right wall, ground (bottom centre).
  const double leftWall = luminanceStdDev(image, 2, 80, 20);
  const double rightWall = luminanceStdDev(image, kWidth - 22, 80, 20);
  const double ground = luminanceStdDev(image, kWidth / 2 - 10, kHeight - 22, 20);
  EXPECT_GT(leftWall, 0.02);
  EXPECT_GT(rightWall, 0.02);
  EXPECT_GT(ground, 0.02);
  // The sun comes from +x: the left wall (facing +x) is brighter than the right one overall.
  auto meanLum = [&](int x0) {
    double sum = 0.0;
    for (int y = 60; y < 120; ++y) {
      for (int x = x0; x < x0 + 10; ++x) sum += image.pixel(x, y)[1];
    }
    return sum / 600.0;
  };
  EXPECT_GT(meanLum(0), meanLum(kWidth - 10));
  for (float v : image.rgba) {
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
  }
}

cv::Mat gray8(const Image& image) {
  cv::Mat gray(image.height, image.width, CV_8UC1);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      const double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      gray.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(255.0 * std::pow(lum, 1.0 / 2.2));
    }
  }
  return gray;
}

TEST_F(SyntheticSceneTest, FeaturesMatchBetweenPathFrames) {
  // What structure from motion needs: many features, most of them matched unambiguously in a
  // frame 5 steps (0.25 m) further along the path.
  const SyntheticView intrinsics = defaultSyntheticIntrinsics(kWidth, kHeight);
  const std::vector<SyntheticPathKey> path = defaultSyntheticPath();
  const cv::Mat a = gray8(renderer().render(syntheticViewAt(intrinsics, path[0])));
  const cv::Mat b = gray8(renderer().render(syntheticViewAt(intrinsics, path[5])));
  cv::Ptr<cv::SIFT> sift = cv::SIFT::create();
  std::vector<cv::KeyPoint> keysA, keysB;
  cv::Mat descA, descB;
  sift->detectAndCompute(a, cv::noArray(), keysA, descA);
  sift->detectAndCompute(b, cv::noArray(), keysB, descB);
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(descA, descB, knn, 2);
  int good = 0;
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < 0.8f * m[1].distance) ++good;
  }
  RecordProperty("sift_keypoints", static_cast<int>(keysA.size()));
  RecordProperty("sift_ratio_matches", good);
  EXPECT_GT(keysA.size(), 200u);
  EXPECT_GT(good, 100);
}

TEST(SyntheticScenePath, MatchesCameraPathConvention) {
  const SyntheticView intrinsics = defaultSyntheticIntrinsics(kWidth, kHeight);
  const std::vector<SyntheticPathKey> keys = defaultSyntheticPath(48);
  ASSERT_EQ(keys.size(), 48u);
  Camera base;
  base.width = intrinsics.width;
  base.height = intrinsics.height;
  base.focalPx = intrinsics.focalPx;
  base.cx = intrinsics.cx;
  base.cy = intrinsics.cy;
  std::vector<std::pair<double, CameraPose>> poses;
  for (const SyntheticPathKey& key : keys) {
    CameraPose pose;
    pose.positionMeters =
        Eigen::Vector3d(key.positionMeters[0], key.positionMeters[1], key.positionMeters[2]);
    pose.yawDeg = key.yawDeg;
    pose.pitchDeg = key.pitchDeg;
    pose.rollDeg = key.rollDeg;
    poses.emplace_back(key.frame, pose);
  }
  const CameraPath path = CameraPath::fromKeys(base, poses);
  for (size_t i = 0; i < keys.size(); ++i) {
    const Camera expected = path.cameraAt(keys[i].frame);
    const SyntheticView view = syntheticViewAt(intrinsics, keys[i]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(view.worldFromCamera[r * 3 + c], expected.worldFromCamera(r, c), 1e-9);
      }
      EXPECT_NEAR(view.positionMeters[r], expected.positionMeters[r], 1e-12);
    }
  }
  // 0.05 m per frame forward, 1.6 m up, some sideways drift and yaw: parallax.
  EXPECT_NEAR(keys.back().positionMeters[2], -0.05 * 47, 1e-12);
  EXPECT_NEAR(keys.back().positionMeters[1], 1.6, 1e-12);
  EXPECT_GT(keys.back().positionMeters[0], 0.2);
  EXPECT_GT(keys.back().yawDeg - keys.front().yawDeg, 2.0);
}

TEST_F(SyntheticSceneTest, RejectsAViewOfAnotherSize) {
  SyntheticView view = defaultSyntheticIntrinsics(kWidth + 1, kHeight);
  EXPECT_THROW(renderer().render(view), Error);
}

}  // namespace
}  // namespace pluvia::lab

namespace pluvia::lab {
TEST(SyntheticView, CameraRoundTripKeepsIntrinsicsAndPose) {
  Camera camera = Camera::fromFieldOfView(320, 180, 50.0, 7.0, 1.6);
  camera.positionMeters = Eigen::Vector3d(0.5, 1.6, -3.0);
  const Camera back = SyntheticView::fromCamera(camera).toCamera<Camera>();
  EXPECT_EQ(back.width, 320);
  EXPECT_EQ(back.height, 180);
  EXPECT_DOUBLE_EQ(back.focalPx, camera.focalPx);
  EXPECT_DOUBLE_EQ(back.cx, camera.cx);
  EXPECT_DOUBLE_EQ(back.cy, camera.cy);
  EXPECT_TRUE(back.worldFromCamera.isApprox(camera.worldFromCamera, 0.0));
  EXPECT_TRUE(back.positionMeters.isApprox(camera.positionMeters, 0.0));
}
}  // namespace pluvia::lab
