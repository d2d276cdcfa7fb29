// COLMAP poses -> pluvia poses, the ground-plane fit, and metric scale, on synthetic scenes whose
// true metric layout is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sfm/ground_plane.h"
#include "sfm/sfm_poses.h"

using namespace pluvia;
using namespace pluvia::sfm;

namespace {

const Eigen::Matrix3d kFlip = Eigen::Vector3d(1, -1, -1).asDiagonal();

ColmapCamera pinhole(int w = 640, int h = 480, double f = 500) {
  ColmapCamera c;
  c.id = 1;
  c.model = "PINHOLE";
  c.width = w;
  c.height = h;
  c.params = {f, f, w / 2.0 + 3.0, h / 2.0 - 2.0};
  return c;
}

// A synthetic scene in pluvia's metric world (ground y = 0 with texture points, a wall at
// z = -12), filmed by cameras 1.6 m up walking toward -Z, then handed to COLMAP's convention in
// an arbitrary model frame x_model = a * Rm * x_world + b.
struct Scene {
  ColmapModel model;
  std::map<std::string, int64_t> frames;
  std::vector<Camera> trueCameras;
  double a = 0.37;
  Eigen::Matrix3d rm =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1.0, 0.5).normalized()).toRotationMatrix();
  Eigen::Vector3d b{4.0, -2.0, 7.5};
};

Scene makeScene(int cameraCount, double stepMeters, double heightMeters = 1.6) {
  Scene s;
  s.model.cameras[1] = pinhole();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> world;
  for (int i = 0; i < 1500; ++i) world.push_back({4.0 * u(rng), 0.0, -8.0 + 6.0 * u(rng)});
  for (int i = 0; i < 600; ++i) world.push_back({5.0 * u(rng), 2.5 + 2.5 * u(rng), -12.0});
  for (size_t i = 0; i < world.size(); ++i) {
    ColmapPoint3D p;
    p.id = static_cast<int64_t>(i) + 100;
    p.xyz = s.a * s.rm * world[i] + s.b;
    p.errorPx = 0.5;
    s.model.points[p.id] = p;
  }
  for (int k = 0; k < cameraCount; ++k) {
    Camera c = Camera::fromFieldOfView(640, 480, 65.0, 8.0, heightMeters);
    c.focalPx = 500;
    c.cx = 323;
    c.cy = 238;
    c.positionMeters = {0.1 * k, heightMeters, -stepMeters * k};
    c.worldFromCamera = Eigen::AngleAxisd(0.05 * k, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                        c.worldFromCamera;
    s.trueCameras.push_back(c);
    ColmapImage im;
    im.id = k + 1;
    im.cameraId = 1;
    im.name = "f" + std::to_string(k) + ".png";
    Eigen::Matrix3d r = kFlip * c.worldFromCamera.transpose() * s.rm.transpose();
    im.qvec = Eigen::Quaterniond(r);
    im.tvec = -r * (s.a * s.rm * c.positionMeters + s.b);
    for (size_t i = 0; i < world.size(); ++i) {
      double x, y, d;
      if (c.project(world[i], x, y, d) && x >= 0 && y >= 0 && x < 640 && y < 480)
        im.observations.push_back({{x, y}, static_cast<int64_t>(i) + 100});
    }
    s.model.images[im.id] = im;
    s.frames[im.name] = 1001 + 2 * k;  // every other clip frame was handed to COLMAP
  }
  return s;
}

}  // namespace

TEST(SfmPoses, ColmapPoseBecomesPluviaPose) {
  ColmapCamera cam = pinhole();
  ColmapImage im;
  im.qvec = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  im.tvec = {0.5, -1.0, 2.0};
  Camera c = pluviaCameraFromColmap(cam, im);
  Eigen::Matrix3d r = im.qvec.toRotationMatrix();
  EXPECT_TRUE(c.positionMeters.isApprox(-r.transpose() * im.tvec, 1e-12));
  // pluvia looks along camera -Z; COLMAP along camera +Z: the same world direction.
  Eigen::Vector3d viewPluvia = c.worldFromCamera * Eigen::Vector3d(0, 0, -1);
  EXPECT_TRUE(viewPluvia.isApprox(r.transpose() * Eigen::Vector3d(0, 0, 1), 1e-12));
  // pluvia's camera up (+Y) is COLMAP's -y.
  EXPECT_TRUE((c.worldFromCamera * Eigen::Vector3d::UnitY())
                  .isApprox(r.transpose() * Eigen::Vector3d(0, -1, 0), 1e-12));
  EXPECT_NEAR(c.worldFromCamera.determinant(), 1.0, 1e-12);
  // Both project a world point to the same pixel and depth.
  Eigen::Vector3d x(0.3, -0.2, 5.0);
  x = -r.transpose() * im.tvec + r.transpose() * x;  // 5 units in front of the camera
  Eigen::Vector3d xc = r * x + im.tvec;
  double px, py, depth;
  ASSERT_TRUE(c.project(x, px, py, depth));
  EXPECT_NEAR(depth, xc.z(), 1e-9);
  EXPECT_NEAR(px, 500 * xc.x() / xc.z() + 323, 1e-9);
  EXPECT_NEAR(py, 500 * xc.y() / xc.z() + 238, 1e-9);
}

TEST(SfmPoses, GroundPlaneFitIgnoresOutliersAndWalls) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.005);
  Eigen::Vector3d n = Eigen::Vector3d(0.1, 1.0, -0.05).normalized();
  Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 400; ++i)  // plane n.x = 0.7 with 5 mm noise
    points.push_back(0.7 * n + 5 * u(rng) * e1 + 5 * u(rng) * e2 + noise(rng) * n);
  for (int i = 0; i < 300; ++i)  // a wall (normal along e1) and scattered clutter
    points.push_back(2.0 * e1 + 3 * u(rng) * e2 + (0.7 + 2 * std::abs(u(rng))) * n);
  for (int i = 0; i < 150; ++i) points.push_back({3 * u(rng), 3 * u(rng), 3 * u(rng)});
  PlaneFitOptions options;
  options.inlierDistance = 0.02;
  PlaneFit fit = fitGroundPlane(points, Eigen::Vector3d(0, 1, 0), options);
  ASSERT_TRUE(fit.found);
  EXPECT_GT(fit.normal.dot(n), std::cos(0.5 * M_PI / 180));  // within 0.5 deg
  EXPECT_NEAR(fit.offset, -0.7, 0.005);
  EXPECT_GE(fit.inliers, 390);
  EXPECT_LE(fit.inliers, 450);
}

TEST(SfmPoses, CameraHeightHintGivesMetricLevelWorld) {
  Scene s = makeScene(8, 0.5);
  SfmOptions options;
  options.scale.cameraHeightMeters = 1.6;
  SfmReconstruction r = reconstructionFromColmap(s.model, s.frames, options);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.groundAtYZero);
  EXPECT_EQ(r.registeredCount, 8);
  EXPECT_DOUBLE_EQ(r.registeredFraction, 1.0);
  EXPECT_NEAR(r.meanReprojectionErrorPx, 0.5, 1e-12);
  EXPECT_NEAR(r.modelToWorld.scale, 1.0 / s.a, 1e-3 / s.a);
  ASSERT_EQ(r.keyframes.size(), 8u);
  for (size_t k = 0; k < 8; ++k) {
    const Camera& c = r.keyframes[k].camera;
    const Camera& t = s.trueCameras[k];
    EXPECT_EQ(r.keyframes[k].frame, 1001 + 2 * static_cast<int64_t>(k));
    // Height is metric; the ground is y = 0 and the first camera sits above the origin, so the
    // rest match the truth up to that shift (the truth's first camera is at x = z = 0 too).
    EXPECT_NEAR(c.positionMeters.y(), 1.6, 1e-3);
    EXPECT_LT((c.positionMeters - t.positionMeters).norm(), 2e-3) << k;
    EXPECT_TRUE(c.worldFromCamera.isApprox(t.worldFromCamera, 1e-4)) << k;
    EXPECT_NEAR(c.focalPx, 500, 1e-12);
  }
  // Ground points land on y = 0.
  int onGround = 0;
  for (const auto& p : r.pointsMeters) onGround += std::abs(p.y()) < 1e-3;
  EXPECT_EQ(onGround, 1500);
  // Between keys the path interpolates: frame 1002 is halfway between the first two cameras.
  Camera mid = r.path.cameraAt(1002);
  EXPECT_LT((mid.positionMeters -
             0.5 * (s.trueCameras[0].positionMeters + s.trueCameras[1].positionMeters))
                .norm(),
            2e-3);
  EXPECT_GT(r.medianDepthMeters, 3.0);
  EXPECT_GT(r.baselineOverDepth, 0.2);
}

TEST(SfmPoses, MedianDepthHintScalesFirstFrame) {
  Scene s = makeScene(6, 0.5);
  SfmOptions options;
  options.scale.firstFrameMedianDepthMeters = 10.0;
  SfmReconstruction r = reconstructionFromColmap(s.model, s.frames, options);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_FALSE(r.groundAtYZero);  // y = 0 is the first camera's height, not the ground
  const SfmKeyframe& first = r.keyframes.front();
  EXPECT_LT(first.camera.positionMeters.norm(), 1e-9);  // the first camera is the origin
  std::vector<double> depths;
  for (int i : first.visiblePoints) {
    double x, y, d;
    ASSERT_TRUE(first.camera.project(r.pointsMeters[i], x, y, d));
    depths.push_back(d);
  }
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  EXPECT_NEAR(depths[depths.size() / 2], 10.0, 1e-6);
  // Levelled by the cameras' mean up: their up axes point along +Y within a few degrees.
  for (const auto& k : r.keyframes)
    EXPECT_GT((k.camera.worldFromCamera * Eigen::Vector3d::UnitY()).y(), std::cos(0.2));
}

TEST(SfmPoses, PanWithoutTravelIsNoParallax) {
  Scene s = makeScene(6, 0.0);
  for (auto& [id, im] : s.model.images)  // also remove the small sideways drift
    im.tvec = -im.cameraFromWorld() * s.model.images.at(1).centre();
  SfmReconstruction r = reconstructionFromColmap(s.model, s.frames, {});
  EXPECT_EQ(r.status, SfmStatus::NoParallax);
  EXPECT_LT(r.baselineOverDepth, 1e-9);
  EXPECT_NE(r.message.find("a pan without travel gives no depth"), std::string::npos) << r.message;
  EXPECT_EQ(r.keyframes.size(), 6u);  // the rotations are still usable
}

TEST(SfmPoses, TooFewRegisteredFrames) {
  Scene s = makeScene(3, 0.5);
  for (int k = 3; k < 10; ++k) s.frames["missing" + std::to_string(k)] = 2000 + k;
  SfmReconstruction r = reconstructionFromColmap(s.model, s.frames, {});
  EXPECT_EQ(r.status, SfmStatus::TooFewRegistered);
  EXPECT_NEAR(r.registeredFraction, 0.3, 1e-12);
  EXPECT_NE(r.message.find("3 of 10"), std::string::npos) << r.message;
}
