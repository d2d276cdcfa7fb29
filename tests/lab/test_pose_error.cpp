// lab/pose_error.h on analytic cases: a path turned by a known yaw and shifted aligns to zero
// error, a 1 degree perturbation of one frame reads 1 degree, a path 1.1 times too large reads a
// scale of 1.1 (and its position error is not hidden by a re-fitted scale), a tilted world reads
// its tilt as the levelling error, and the depth metric on small hand-made arrays.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "lab/pose_error.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::lab;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr float kInf = std::numeric_limits<float>::infinity();

// A walk down -Z at 1.6 m, drifting right, yawing and pitching a little (like the synthetic
// path of the depth report): nearly collinear centres.
std::vector<Camera> truePath(int frames = 48) {
  std::vector<std::pair<double, CameraPose>> keys;
  for (int i = 0; i < frames; ++i) {
    CameraPose pose;
    pose.positionMeters = Eigen::Vector3d(0.01 * i, 1.6, -0.05 * i);
    pose.yawDeg = 4.0 * (i / double(frames - 1) - 0.5);
    pose.pitchDeg = -3.0 + 0.5 * std::sin(0.3 * i);
    pose.rollDeg = 0.2 * std::cos(0.2 * i);
    keys.push_back({double(i), pose});
  }
  const Camera intrinsics = Camera::fromFieldOfView(320, 180, 60.0, 0.0, 1.6);
  const CameraPath path = CameraPath::fromKeys(intrinsics, keys);
  std::vector<Camera> cameras;
  for (int i = 0; i < frames; ++i) cameras.push_back(path.cameraAt(i));
  return cameras;
}

// The cameras as seen from another world: x_other = rotation * x + shift (scaled about the
// origin by `scale` first).
std::vector<Camera> transformed(const std::vector<Camera>& cameras, const Eigen::Matrix3d& rotation,
                                const Eigen::Vector3d& shift, double scale = 1.0) {
  std::vector<Camera> out = cameras;
  for (Camera& camera : out) {
    camera.worldFromCamera = rotation * camera.worldFromCamera;
    camera.positionMeters = rotation * (scale * camera.positionMeters) + shift;
  }
  return out;
}

Eigen::Matrix3d yaw(double degrees) {
  return Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

TEST(PoseError, YawedAndShiftedPathAlignsToZeroError) {
  const std::vector<Camera> truth = truePath();
  const std::vector<Camera> estimate =
      transformed(truth, yaw(137.0), Eigen::Vector3d(12.0, 0.0, -40.0));
  const PoseErrors errors = comparePoses(truth, estimate);
  EXPECT_LT(errors.maxRotationErrorDeg, 1e-6);
  EXPECT_LT(errors.maxPositionErrorMeters, 1e-9);
  EXPECT_NEAR(errors.scaleRatio, 1.0, 1e-9);
  EXPECT_LT(errors.levelErrorDeg, 1e-6);
  EXPECT_NEAR(errors.heightOffsetMeters, 0.0, 1e-12);
  // The alignment undoes the yaw: truth = R * estimate + t.
  EXPECT_LT(rotationAngleDeg(errors.alignment.rotation * yaw(137.0)), 1e-6);
  ASSERT_EQ(errors.rotationErrorDeg.size(), truth.size());
  ASSERT_EQ(errors.positionErrorMeters.size(), truth.size());
}

TEST(PoseError, OneFramePerturbedByOneDegreeReadsOneDegree) {
  const std::vector<Camera> truth = truePath();
  std::vector<Camera> estimate = transformed(truth, yaw(-70.0), Eigen::Vector3d(3.0, 0.0, 5.0));
  const int bad = 20;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, -0.2).normalized();
  estimate[bad].worldFromCamera =
      Eigen::AngleAxisd(1.0 * kDeg, axis).toRotationMatrix() * estimate[bad].worldFromCamera;
  const PoseErrors errors = comparePoses(truth, estimate);
  // The chordal mean moves by about 1/N of the perturbation: the frame reads 1 - 1/N degrees,
  // the others 1/N.
  const double n = double(truth.size());
  EXPECT_NEAR(errors.rotationErrorDeg[bad], 1.0, 1.5 / n);
  EXPECT_NEAR(errors.maxRotationErrorDeg, errors.rotationErrorDeg[bad], 1e-12);
  for (size_t i = 0; i < truth.size(); ++i) {
    if (int(i) == bad) continue;
    EXPECT_LT(errors.rotationErrorDeg[i], 1.5 / n) << i;
  }
  EXPECT_NEAR(errors.meanRotationErrorDeg, 2.0 / n, 0.5 / n);
  // Positions are untouched; the small turn of the alignment moves them by millimetres.
  EXPECT_LT(errors.maxPositionErrorMeters, 0.01);
}

TEST(PoseError, ScaleIsReportedAndNotRefitted) {
  const std::vector<Camera> truth = truePath();
  // 10 % too large about the path's own centre (the height stays right on the mean).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Camera& c : truth) centre += c.positionMeters;
  centre /= double(truth.size());
  std::vector<Camera> estimate = truth;
  for (Camera& c : estimate) c.positionMeters = centre + 1.1 * (c.positionMeters - centre);
  estimate = transformed(estimate, yaw(25.0), Eigen::Vector3d(-1.0, 0.0, 2.0));
  const PoseErrors errors = comparePoses(truth, estimate);
  EXPECT_NEAR(errors.scaleRatio, 1.1, 1e-9);
  EXPECT_LT(errors.maxRotationErrorDeg, 1e-6);
  // Without a re-fitted scale the ends of the 2.4 m walk are 5 % of half of it off.
  double halfLength = 0.0;
  for (const Camera& c : truth)
    halfLength = std::max(halfLength, (c.positionMeters - centre).norm());
  EXPECT_NEAR(errors.maxPositionErrorMeters, 0.1 * halfLength, 1e-9);
  EXPECT_GT(errors.meanPositionErrorMeters, 0.01);
}

TEST(PoseError, TiltedWorldReadsItsLevellingErrorAndHeight) {
  const std::vector<Camera> truth = truePath();
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const std::vector<Camera> estimate =
      transformed(truth, tilt * yaw(10.0), Eigen::Vector3d(0.0, 0.3, 0.0));
  const PoseErrors errors = comparePoses(truth, estimate);
  EXPECT_NEAR(errors.levelErrorDeg, 2.0, 1e-6);
  EXPECT_LT(errors.maxRotationErrorDeg, 1e-6);
  EXPECT_LT(errors.maxPositionErrorMeters, 1e-9);
}

TEST(PoseError, RejectsMismatchedLengths) {
  const std::vector<Camera> truth = truePath(4);
  EXPECT_THROW(comparePoses(truth, truePath(3)), Error);
  EXPECT_THROW(comparePoses({}, {}), Error);
}

TEST(PoseError, RotationAngleNearZeroAndNearHalfTurn) {
  for (double degrees : {1e-5, 0.01, 1.0, 90.0, 179.9, 180.0}) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    EXPECT_NEAR(rotationAngleDeg(r), degrees, 1e-7 * std::max(1.0, degrees)) << degrees;
  }
}

TEST(DepthError, HandMadeArrays) {
  // truth:    2, 4, 10, inf, inf, 5, 8
  // estimate: 2.2 (10 %), 3 (25 %), 10 (0), inf (sky right), 50 (sky missed), inf (hole), 8 (0)
  const std::vector<float> truth = {2.0f, 4.0f, 10.0f, kInf, kInf, 5.0f, 8.0f};
  const std::vector<float> estimate = {2.2f, 3.0f, 10.0f, kInf, 50.0f, kInf, 8.0f};
  const DepthErrors errors = compareDepth(truth, estimate);
  EXPECT_EQ(errors.comparedPixels, 4u);  // 2, 4, 10, 8
  EXPECT_EQ(errors.skyPixels, 2u);
  EXPECT_EQ(errors.nonSkyPixels, 5u);
  EXPECT_DOUBLE_EQ(errors.skyAsInfinityFraction, 0.5);
  EXPECT_DOUBLE_EQ(errors.nonSkyAsInfinityFraction, 0.2);
  // Sorted relative errors 0, 0, 0.1, 0.25: the nearest-rank median is the third.
  EXPECT_NEAR(errors.medianRelativeError, 0.1, 1e-6);
  EXPECT_NEAR(errors.p90RelativeError, 0.25, 1e-6);
}

TEST(DepthError, MaskAndPoolingAndEmptyCases) {
  const std::vector<float> truth = {1.0f, 2.0f, 3.0f};
  const std::vector<float> estimate = {1.5f, 2.0f, 3.0f};
  const std::vector<uint8_t> onlyFirst = {1, 0, 0};
  DepthErrors errors = compareDepth(truth, estimate, &onlyFirst);
  EXPECT_EQ(errors.comparedPixels, 1u);
  EXPECT_NEAR(errors.medianRelativeError, 0.5, 1e-6);
  EXPECT_TRUE(std::isnan(errors.skyAsInfinityFraction));  // no sky in the truth

  DepthErrorAccumulator pooled;
  pooled.add(truth, estimate);             // 0.5, 0, 0
  pooled.add({4.0f, kInf}, {6.0f, kInf});  // 0.5; sky right
  errors = pooled.result();
  EXPECT_EQ(errors.comparedPixels, 4u);
  EXPECT_NEAR(errors.medianRelativeError, 0.5, 1e-6);  // 0, 0, 0.5, 0.5: rank 2 of 0..3
  EXPECT_DOUBLE_EQ(errors.skyAsInfinityFraction, 1.0);
  EXPECT_DOUBLE_EQ(errors.nonSkyAsInfinityFraction, 0.0);

  errors = compareDepth({kInf}, {kInf});
  EXPECT_EQ(errors.comparedPixels, 0u);
  EXPECT_TRUE(std::isnan(errors.medianRelativeError));
  EXPECT_THROW(compareDepth({1.0f}, {1.0f, 2.0f}), Error);
}

}  // namespace
