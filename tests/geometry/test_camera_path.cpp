#include <gtest/gtest.h>

#include <cmath>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "util/error.h"

using namespace pluvia;

namespace {
CameraPose pose(double x, double y, double z, double yaw = 0, double pitch = 0, double roll = 0) {
  CameraPose p;
  p.positionMeters = {x, y, z};
  p.yawDeg = yaw;
  p.pitchDeg = pitch;
  p.rollDeg = roll;
  return p;
}

// Where the camera looks, in world space.
Eigen::Vector3d forward(const Camera& c) {
  return c.worldFromCamera * Eigen::Vector3d(0, 0, -1);
}

// The heading of the view in degrees, from -Z toward +X.
double headingDeg(const Camera& c) {
  Eigen::Vector3d f = forward(c);
  return std::atan2(f.x(), -f.z()) * 180.0 / M_PI;
}

void expectSameCamera(const Camera& a, const Camera& b, double tolerance = 1e-12) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_DOUBLE_EQ(a.focalPx, b.focalPx);
  EXPECT_DOUBLE_EQ(a.cx, b.cx);
  EXPECT_DOUBLE_EQ(a.cy, b.cy);
  EXPECT_TRUE(a.worldFromCamera.isApprox(b.worldFromCamera, tolerance))
      << a.worldFromCamera << "\n\n"
      << b.worldFromCamera;
  EXPECT_LE((a.positionMeters - b.positionMeters).norm(), tolerance);
}
}  // namespace

TEST(CameraPath, ConventionsYawRightPitchUpRollRightDown) {
  EXPECT_TRUE(worldFromCameraRotation(pose(0, 0, 0)).isIdentity(1e-15));
  Eigen::Vector3d f = worldFromCameraRotation(pose(0, 0, 0, 90)) * Eigen::Vector3d(0, 0, -1);
  EXPECT_LT((f - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);  // yaw +90: looks along +X
  f = worldFromCameraRotation(pose(0, 0, 0, 0, 30)) * Eigen::Vector3d(0, 0, -1);
  EXPECT_NEAR(f.y(), std::sin(30 * M_PI / 180), 1e-12);  // pitch up
  Eigen::Vector3d right =
      worldFromCameraRotation(pose(0, 0, 0, 0, 0, 10)) * Eigen::Vector3d(1, 0, 0);
  EXPECT_LT(right.y(), 0.0);  // roll: the right side goes down
}

TEST(CameraPath, FixedPathIsTheBaseCamera) {
  Camera base = Camera::fromFieldOfView(1920, 1080, 50, 12, 2.5);
  CameraPath path = CameraPath::fixed(base);
  EXPECT_FALSE(path.moving());
  for (double frame : {-100.0, 0.0, 1001.5, 1e6}) expectSameCamera(path.cameraAt(frame), base, 0.0);
  // No keys: fixed as well.
  EXPECT_FALSE(CameraPath::fromKeys(base, {}).moving());
  expectSameCamera(CameraPath::fromKeys(base, {}).cameraAt(3), base, 0.0);
}

TEST(CameraPath, SingleKeyMatchesFromFieldOfView) {
  for (double tilt : {-30.0, 0.0, 15.0, 60.0}) {
    Camera expected = Camera::fromFieldOfView(1280, 720, 40, tilt, 3.0);
    Camera intrinsics = Camera::fromFieldOfView(1280, 720, 40, 0, 0);
    CameraPath path = CameraPath::fromKeys(intrinsics, {{1001, pose(0, 3.0, 0, 0, -tilt)}});
    EXPECT_FALSE(path.moving());
    expectSameCamera(path.cameraAt(1001), expected);
    expectSameCamera(path.cameraAt(0), expected);        // held before
    expectSameCamera(path.cameraAt(5000.25), expected);  // and after
    // Projections agree too.
    double ax, ay, ad, bx, by, bd;
    ASSERT_TRUE(expected.project({1.0, 2.0, -10.0}, ax, ay, ad));
    ASSERT_TRUE(path.cameraAt(1001).project({1.0, 2.0, -10.0}, bx, by, bd));
    EXPECT_NEAR(ax, bx, 1e-9);
    EXPECT_NEAR(ay, by, 1e-9);
    EXPECT_NEAR(ad, bd, 1e-12);
  }
}

TEST(CameraPath, InterpolatesAtAndBetweenKeysAndHoldsOutside) {
  Camera intrinsics = Camera::fromFieldOfView(640, 480, 60, 0, 0);
  CameraPath path = CameraPath::fromKeys(
      intrinsics,
      {{10, pose(0, 1, 0, 0)}, {20, pose(10, 3, -4, 40)}, {40, pose(10, 3, -4, 40, 20)}});
  EXPECT_TRUE(path.moving());
  EXPECT_EQ(path.keys().size(), 3u);
  expectSameCamera(path.cameraAt(10),
                   CameraPath::fromKeys(intrinsics, {{0, pose(0, 1, 0, 0)}}).cameraAt(0));
  Camera at20 = path.cameraAt(20);
  EXPECT_LT((at20.positionMeters - Eigen::Vector3d(10, 3, -4)).norm(), 1e-12);
  EXPECT_TRUE(at20.worldFromCamera.isApprox(worldFromCameraRotation(pose(0, 0, 0, 40)), 1e-12));
  // Between keys: position linear, yaw halfway (a rotation about one axis slerps linearly in
  // angle).
  Camera mid = path.cameraAt(15);
  EXPECT_LT((mid.positionMeters - Eigen::Vector3d(5, 2, -2)).norm(), 1e-12);
  EXPECT_NEAR(headingDeg(mid), 20.0, 1e-9);
  Camera quarter = path.cameraAt(12.5);  // fractional frames
  EXPECT_LT((quarter.positionMeters - Eigen::Vector3d(2.5, 1.5, -1)).norm(), 1e-12);
  EXPECT_NEAR(headingDeg(quarter), 10.0, 1e-9);
  // Pitch between the last two keys.
  Camera at30 = path.cameraAt(30);
  EXPECT_NEAR(std::asin(forward(at30).y()) * 180 / M_PI, 10.0, 1e-9);
  EXPECT_NEAR(headingDeg(at30), 40.0, 1e-9);
  // Held outside the range.
  expectSameCamera(path.cameraAt(-3), path.cameraAt(10));
  expectSameCamera(path.cameraAt(41), path.cameraAt(40));
  // Intrinsics are kept.
  EXPECT_DOUBLE_EQ(mid.focalPx, intrinsics.focalPx);
  EXPECT_EQ(mid.width, 640);
}

TEST(CameraPath, YawWrapsTheShortWay) {
  Camera intrinsics = Camera::fromFieldOfView(640, 480, 60, 0, 0);
  CameraPath path =
      CameraPath::fromKeys(intrinsics, {{0, pose(0, 1, 0, 350)}, {10, pose(0, 1, 0, 10)}});
  EXPECT_NEAR(headingDeg(path.cameraAt(5)), 0.0, 1e-9);  // not 180
  EXPECT_NEAR(headingDeg(path.cameraAt(2.5)), -5.0, 1e-9);
  EXPECT_NEAR(headingDeg(path.cameraAt(7.5)), 5.0, 1e-9);
  CameraPath back =
      CameraPath::fromKeys(intrinsics, {{0, pose(0, 1, 0, -170)}, {10, pose(0, 1, 0, 170)}});
  EXPECT_NEAR(std::abs(headingDeg(back.cameraAt(5))), 180.0, 1e-9);
}

TEST(CameraPath, PerFramePosesAndBadKeys) {
  Camera intrinsics = Camera::fromFieldOfView(640, 480, 60, 0, 0);
  std::vector<std::pair<double, CameraPose>> perFrame;
  for (int f = 1001; f <= 1010; ++f)
    perFrame.emplace_back(f, pose(0.1 * (f - 1001), 1.5, 0, f - 1001));
  CameraPath path(intrinsics, perFrame);
  EXPECT_NEAR(path.cameraAt(1005).positionMeters.x(), 0.4, 1e-12);
  EXPECT_NEAR(headingDeg(path.cameraAt(1005.5)), 4.5, 1e-9);
  EXPECT_THROW(CameraPath::fromKeys(intrinsics, {{5, pose(0, 1, 0)}, {5, pose(1, 1, 0)}}), Error);
  EXPECT_THROW(CameraPath::fromKeys(intrinsics, {{5, pose(0, 1, 0)}, {4, pose(1, 1, 0)}}), Error);
  EXPECT_THROW(CameraPath::fromKeys(intrinsics, {{0, pose(NAN, 1, 0)}}), Error);
  EXPECT_THROW(CameraPath::fromKeys(intrinsics, {{0, pose(0, 1, 0, INFINITY)}}), Error);
  // Keys as rotations (a tracker's output).
  CameraPathKey key;
  key.frame = 3;
  key.positionMeters = {1, 2, 3};
  key.worldFromCamera = Eigen::Quaterniond(worldFromCameraRotation(pose(0, 0, 0, 30, -10, 5)));
  Camera fromRotation = CameraPath::fromRotations(intrinsics, {key}).cameraAt(0);
  Camera fromPose = CameraPath::fromKeys(intrinsics, {{3, pose(1, 2, 3, 30, -10, 5)}}).cameraAt(0);
  expectSameCamera(fromRotation, fromPose);
}
