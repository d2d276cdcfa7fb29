#include "lab/pose_error.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "util/error.h"
#include "util/median.h"

namespace pluvia::lab {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// The rotation nearest to `m` in the Frobenius norm.
Eigen::Matrix3d projectToRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

}  // namespace

double rotationAngleDeg(const Eigen::Matrix3d& rotation) {
  // atan2 of the axis part against the trace part: accurate at small and near-180 angles, where
  // acos((trace - 1) / 2) loses precision.
  const Eigen::Vector3d axis(rotation(2, 1) - rotation(1, 2), rotation(0, 2) - rotation(2, 0),
                             rotation(1, 0) - rotation(0, 1));
  const double cosine = rotation.trace() - 1.0;  // 2 cos(theta)
  return std::atan2(axis.norm(), cosine) * kRadToDeg;
}

PoseErrors comparePoses(const std::vector<Camera>& truth, const std::vector<Camera>& estimate) {
  if (truth.empty() || truth.size() != estimate.size())
    throw Error("comparePoses: " + std::to_string(truth.size()) + " true and " +
                std::to_string(estimate.size()) + " estimated cameras (need the same, >= 1)");
  const size_t n = truth.size();
  PoseErrors errors;

  // Rotation: chordal mean of R_true R_est^T.
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i)
    sum += truth[i].worldFromCamera * estimate[i].worldFromCamera.transpose();
  const Eigen::Matrix3d rotation = projectToRotation(sum);

  // Translation: mean centres onto each other, no scale.
  Eigen::Vector3d meanTrue = Eigen::Vector3d::Zero(), meanEst = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    meanTrue += truth[i].positionMeters;
    meanEst += estimate[i].positionMeters;
  }
  meanTrue /= static_cast<double>(n);
  meanEst /= static_cast<double>(n);
  errors.alignment.rotation = rotation;
  errors.alignment.translationMeters = meanTrue - rotation * meanEst;
  errors.heightOffsetMeters = meanEst.y() - meanTrue.y();
  errors.levelErrorDeg =
      std::acos(std::clamp((rotation * Eigen::Vector3d::UnitY()).y(), -1.0, 1.0)) * kRadToDeg;

  // Scale (reported, not applied): argmin_s sum |R d_est - s d_true|^2.
  double cross = 0.0, trueSquared = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d dTrue = truth[i].positionMeters - meanTrue;
    const Eigen::Vector3d dEst = rotation * (estimate[i].positionMeters - meanEst);
    cross += dEst.dot(dTrue);
    trueSquared += dTrue.squaredNorm();
  }
  errors.scaleRatio = trueSquared > 1e-18 ? cross / trueSquared : kNaN;

  double rotationSum = 0.0, positionSum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double angle = rotationAngleDeg(truth[i].worldFromCamera.transpose() * rotation *
                                          estimate[i].worldFromCamera);
    const Eigen::Vector3d aligned =
        rotation * estimate[i].positionMeters + errors.alignment.translationMeters;
    const double distance = (aligned - truth[i].positionMeters).norm();
    errors.rotationErrorDeg.push_back(angle);
    errors.positionErrorMeters.push_back(distance);
    rotationSum += angle;
    positionSum += distance;
    errors.maxRotationErrorDeg = std::max(errors.maxRotationErrorDeg, angle);
    errors.maxPositionErrorMeters = std::max(errors.maxPositionErrorMeters, distance);
  }
  errors.meanRotationErrorDeg = rotationSum / static_cast<double>(n);
  errors.meanPositionErrorMeters = positionSum / static_cast<double>(n);
  return errors;
}

void DepthErrorAccumulator::add(const std::vector<float>& truth, const std::vector<float>& estimate,
                                const std::vector<uint8_t>* include) {
  if (truth.size() != estimate.size() || (include && include->size() != truth.size()))
    throw Error("compareDepth: depth maps of " + std::to_string(truth.size()) + " and " +
                std::to_string(estimate.size()) + " pixels" +
                (include ? " (mask " + std::to_string(include->size()) + ")" : std::string()));
  for (size_t i = 0; i < truth.size(); ++i) {
    if (include && !(*include)[i]) continue;
    const float t = truth[i], e = estimate[i];
    if (std::isnan(t)) continue;
    const bool estimateInfinite = std::isinf(e) && e > 0.0f;
    if (std::isinf(t)) {
      ++skyPixels_;
      skyAsInfinity_ += estimateInfinite;
      continue;
    }
    ++nonSkyPixels_;
    nonSkyAsInfinity_ += estimateInfinite;
    if (t > 0.0f && std::isfinite(e) && e > 0.0f) relativeErrors_.push_back(std::fabs(e - t) / t);
  }
}

DepthErrors DepthErrorAccumulator::result() const {
  DepthErrors errors;
  std::vector<float> values = relativeErrors_;
  errors.comparedPixels = values.size();
  errors.medianRelativeError = quantileInPlace(values, 0.5);
  errors.p90RelativeError = quantileInPlace(values, 0.9);
  errors.skyPixels = skyPixels_;
  errors.nonSkyPixels = nonSkyPixels_;
  errors.skyAsInfinityFraction =
      skyPixels_ > 0 ? static_cast<double>(skyAsInfinity_) / static_cast<double>(skyPixels_) : kNaN;
  errors.nonSkyAsInfinityFraction = nonSkyPixels_ > 0 ? static_cast<double>(nonSkyAsInfinity_) /
                                                            static_cast<double>(nonSkyPixels_)
                                                      : kNaN;
  return errors;
}

DepthErrors compareDepth(const std::vector<float>& truth, const std::vector<float>& estimate,
                         const std::vector<uint8_t>* include) {
  DepthErrorAccumulator accumulator;
  accumulator.add(truth, estimate, include);
  return accumulator.result();
}

}  // namespace pluvia::lab
