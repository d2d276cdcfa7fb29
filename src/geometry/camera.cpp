#include "geometry/camera.h"

#include <cmath>

#include <Eigen/Geometry>

namespace pluvia {

Camera Camera::fromFieldOfView(int width, int height, double hfovDeg, double tiltDownDeg,
                               double heightMeters) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.focalPx = 0.5 * width / std::tan(0.5 * hfovDeg * M_PI / 180.0);
  camera.cx = 0.5 * width;
  camera.cy = 0.5 * height;
  // Pitching down is a negative rotation about +X (looking along -Z, +Y up).
  camera.worldFromCamera =
      Eigen::AngleAxisd(-tiltDownDeg * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  camera.positionMeters = Eigen::Vector3d(0.0, heightMeters, 0.0);
  return camera;
}

Eigen::Vector3d Camera::rayCamera(double px, double py) const {
  return {(px - cx) / focalPx, -(py - cy) / focalPx, -1.0};
}

bool Camera::project(const Eigen::Vector3d& world, double& px, double& py, double& depthMeters,
                     double minDepthMeters) const {
  Eigen::Vector3d local = worldFromCamera.transpose() * (world - positionMeters);
  depthMeters = -local.z();
  if (depthMeters <= minDepthMeters) return false;
  px = cx + focalPx * local.x() / depthMeters;
  py = cy - focalPx * local.y() / depthMeters;
  return true;
}

}  // namespace pluvia
