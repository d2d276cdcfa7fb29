#include "geometry/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "util/error.h"

namespace pluvia {

namespace {
constexpr double kDegrees = M_PI / 180.0;

std::string frameText(double frame) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", frame);
  return text;
}
}  // namespace

Eigen::Matrix3d worldFromCameraRotation(const CameraPose& pose) {
  return (Eigen::AngleAxisd(-pose.yawDeg * kDegrees, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pose.pitchDeg * kDegrees, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(-pose.rollDeg * kDegrees, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

CameraPath::CameraPath(const Camera& intrinsics,
                       const std::vector<std::pair<double, CameraPose>>& keys) {
  std::vector<CameraPathKey> converted;
  converted.reserve(keys.size());
  for (const auto& [frame, pose] : keys) {
    if (!std::isfinite(pose.yawDeg) || !std::isfinite(pose.pitchDeg) ||
        !std::isfinite(pose.rollDeg))
      throw Error("camera path: the key at frame " + frameText(frame) + " has a non-finite angle");
    converted.push_back(
        {frame, pose.positionMeters, Eigen::Quaterniond(worldFromCameraRotation(pose))});
  }
  *this = fromRotations(intrinsics, std::move(converted));
}

CameraPath CameraPath::fixed(const Camera& camera) {
  CameraPath path;
  path.base_ = camera;
  return path;
}

CameraPath CameraPath::fromKeys(const Camera& intrinsicsAndBase,
                                std::vector<std::pair<double, CameraPose>> keys) {
  return CameraPath(intrinsicsAndBase, keys);
}

CameraPath CameraPath::fromRotations(const Camera& intrinsics, std::vector<CameraPathKey> keys) {
  for (size_t i = 0; i < keys.size(); ++i) {
    const CameraPathKey& key = keys[i];
    if (!std::isfinite(key.frame))
      throw Error("camera path: key " + std::to_string(i) + " has a non-finite frame");
    if (!key.positionMeters.allFinite() || !key.worldFromCamera.coeffs().allFinite() ||
        key.worldFromCamera.norm() < 1e-12)
      throw Error("camera path: the key at frame " + frameText(key.frame) +
                  " has a non-finite pose");
    if (i > 0 && !(key.frame > keys[i - 1].frame))
      throw Error("camera path: frames must increase strictly (frame " + frameText(key.frame) +
                  " after " + frameText(keys[i - 1].frame) + ")");
  }
  CameraPath path;
  path.base_ = intrinsics;
  path.keys_ = std::move(keys);
  for (auto& key : path.keys_) key.worldFromCamera.normalize();
  return path;
}

Camera CameraPath::cameraAt(double frame) const {
  if (keys_.empty()) return base_;
  Camera camera = base_;
  const CameraPathKey* a = &keys_.front();
  const CameraPathKey* b = a;
  double t = 0.0;
  if (frame >= keys_.back().frame) {
    a = b = &keys_.back();
  } else if (frame > keys_.front().frame) {
    auto next = std::upper_bound(keys_.begin(), keys_.end(), frame,
                                 [](double f, const CameraPathKey& key) { return f < key.frame; });
    b = &*next;
    a = &*(next - 1);
    t = (frame - a->frame) / (b->frame - a->frame);
  }
  camera.positionMeters = a->positionMeters + t * (b->positionMeters - a->positionMeters);
  // Eigen's slerp takes the shorter arc (it flips b when the dot product is negative).
  camera.worldFromCamera = a->worldFromCamera.slerp(t, b->worldFromCamera).toRotationMatrix();
  return camera;
}

bool CameraPath::moving() const {
  for (size_t i = 1; i < keys_.size(); ++i) {
    if (keys_[i].positionMeters != keys_[0].positionMeters ||
        keys_[i].worldFromCamera.angularDistance(keys_[0].worldFromCamera) > 1e-10)
      return true;
  }
  return false;
}

}  // namespace pluvia
