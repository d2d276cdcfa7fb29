#pragma once
// A pinhole camera in pluvia's world frame: +Y up, metres. In camera space the camera looks
// along -Z with +Y up and +X right (the optics conventions); pixels have their origin at the
// top-left corner with y down, and pixel centres at +0.5.
#include <Eigen/Core>

namespace pluvia {

struct Camera {
  int width = 0;
  int height = 0;
  double focalPx = 1.0;  // same for x and y (square pixels)
  double cx = 0.0;       // principal point, pixels
  double cy = 0.0;
  Eigen::Matrix3d worldFromCamera = Eigen::Matrix3d::Identity();
  Eigen::Vector3d positionMeters = Eigen::Vector3d::Zero();

  // Camera at height `heightMeters` above the ground plane y = 0, pitched down by tiltDownDeg,
  // with horizontal field of view hfovDeg.
  static Camera fromFieldOfView(int width, int height, double hfovDeg, double tiltDownDeg,
                                double heightMeters);

  // Direction in camera space through pixel position (px, py), scaled so that z = -1.
  Eigen::Vector3d rayCamera(double px, double py) const;
  // Projects a world point. Returns false when it lies behind the camera (z-depth <= minDepth).
  bool project(const Eigen::Vector3d& world, double& px, double& py, double& depthMeters,
               double minDepthMeters = 1e-3) const;
};

}  // namespace pluvia
