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

// The ground under a walking or driving camera: as fitGroundPlane, but only planes below every
// camera are candidates, and the normal is refitted to the ground inliers and the camera centres
// together (the smallest eigenvector of the sum of their covariances, each over its own count):
// the plane along which the ground is flat and the cameras ride at one height. A street's points
// constrain the tilt across the path well and the tilt along it poorly (its far end is a few
// noisy points); the cameras constrain exactly that. When the joint normal is further than
// maxCameraTiltDeg from the ground points' own (a crane shot, a drone climbing), or the joint
// plane passes over a camera, the points' plane is kept and `camerasUsed` is false. RANSAC's
// candidates must pass the inlier band below every camera; the joint plane only below.
struct GroundBelowCameras {
  PlaneFit plane;
  bool camerasUsed = false;
  double pointsOnlyTiltDeg = 0.0;  // the joint normal's angle from the points' own
};
GroundBelowCameras fitGroundBelowCameras(const std::vector<Eigen::Vector3d>& points,
                                         const std::vector<Eigen::Vector3d>& cameras,
                                         const Eigen::Vector3d& up,
                                         const PlaneFitOptions& options = {},
                                         double maxCameraTiltDeg = 5.0);

}  // namespace pluvia::sfm
