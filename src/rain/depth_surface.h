#pragma once
// The surfaces a frame's z-depth plane shows, as the rain's ground stages read them (splashes,
// ripples, wet ground): a pixel's world point, and whether two neighbours lie on one surface.
#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace pluvia::rain {

// Neighbours whose depths differ by more than this share of the nearer are not one surface (ground
// seen at a grazing angle changes faster than 5 % per pixel in a small frame, hence the margin).
inline constexpr double kDepthDiscontinuity = 0.25;

// The world point at pixel position (px, py) and z-depth `depth` (metres).
inline Eigen::Vector3d worldPoint(const Camera& camera, double px, double py, double depth) {
  return camera.positionMeters + camera.worldFromCamera * (camera.rayCamera(px, py) * depth);
}

// Two z-depths on one surface: both finite and positive, within kDepthDiscontinuity.
inline bool depthsContinuous(double a, double b) {
  return std::isfinite(a) && std::isfinite(b) && a > 0.0 && b > 0.0 &&
         std::abs(a - b) <= kDepthDiscontinuity * std::min(a, b);
}

}  // namespace pluvia::rain
