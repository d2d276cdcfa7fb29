#pragma once
// A RANSAC ground plane for metric scale: COLMAP models are up to scale, and the camera's height
// above the ground is a number a user usually knows.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace pluvia::sfm {

struct PlaneFit {
  bool found = false;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // unit, points toward `up`
  double offset = 0.0;  // plane: normal . x + offset = 0; signed distance = normal . x + offset
  int inliers = 0;      // points within inlierDistance of the final plane
};

struct PlaneFitOptions {
  // A point is an inlier within this distance of the plane (model units).
  double inlierDistance = 0.05;
  // Candidate planes whose normal is further than this from `up` are rejected: the ground is
  // roughly level relative to the cameras, walls are not.
  double maxTiltDeg = 30.0;
  int iterations = 500;
  uint32_t seed = 12345;  // fixed: the same points give the same plane
};

// Fits a plane to `points` whose normal lies within maxTiltDeg of `up`, by RANSAC over point
// triples and a least-squares refit on the inliers. `found` is false with fewer than 3 points or
// no acceptable plane.
PlaneFit fitGroundPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                        const PlaneFitOptions& options = {});

}  // namespace pluvia::sfm
