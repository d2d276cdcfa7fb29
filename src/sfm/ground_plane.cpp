#include "sfm/ground_plane.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

namespace pluvia::sfm {
namespace {

// Least-squares plane through points: the normal is the covariance's smallest eigenvector.
void refit(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& inliers,
           PlaneFit& fit) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : inliers) mean += points[i];
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i : inliers) cov += (points[i] - mean) * (points[i] - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
  if (n.dot(fit.normal) < 0) n = -n;
  fit.normal = n;
  fit.offset = -n.dot(mean);
}

Eigen::Matrix3d covariance(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& use,
                           Eigen::Vector3d& mean) {
  mean = Eigen::Vector3d::Zero();
  for (int i : use) mean += points[i];
  mean /= static_cast<double>(use.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i : use) cov += (points[i] - mean) * (points[i] - mean).transpose();
  return cov / static_cast<double>(use.size());
}

std::vector<int> within(const std::vector<Eigen::Vector3d>& points, const PlaneFit& plane,
                        double band) {
  std::vector<int> inside;
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
    if (std::abs(plane.normal.dot(points[i]) + plane.offset) < band) inside.push_back(i);
  return inside;
}

// fitGroundPlane, with candidate planes also passing `accept`.
template <typename Accept>
PlaneFit fitPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                  const PlaneFitOptions& options, Accept accept) {
  PlaneFit best;
  const int n = static_cast<int>(points.size());
  if (n < 3 || up.norm() < 1e-12) return best;
  const Eigen::Vector3d upUnit = up.normalized();
  const double minCos = std::cos(options.maxTiltDeg * M_PI / 180.0);
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> bestInliers;
  for (int it = 0; it < options.iterations; ++it) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || b == c || a == c) continue;
    Eigen::Vector3d normal = (points[b] - points[a]).cross(points[c] - points[a]);
    if (normal.norm() < 1e-12) continue;
    normal.normalize();
    if (normal.dot(upUnit) < 0) normal = -normal;
    if (normal.dot(upUnit) < minCos) continue;
    double offset = -normal.dot(points[a]);
    if (!accept(normal, offset)) continue;
    std::vector<int> inliers;
    for (int i = 0; i < n; ++i)
      if (std::abs(normal.dot(points[i]) + offset) < options.inlierDistance) inliers.push_back(i);
    if (inliers.size() > bestInliers.size()) {
      bestInliers = std::move(inliers);
      best.normal = normal;
      best.offset = offset;
    }
  }
  if (bestInliers.size() < 3) return best;
  best.found = true;
  refit(points, bestInliers, best);
  // Refits with a narrowing band: points at the foot of walls or kerbs fall inside the coarse
  // RANSAC band and would tilt a least-squares plane; a quarter of the band excludes most.
  for (double band : {0.5 * options.inlierDistance, 0.25 * options.inlierDistance}) {
    std::vector<int> next;
    for (int i = 0; i < n; ++i)
      if (std::abs(best.normal.dot(points[i]) + best.offset) < band) next.push_back(i);
    if (next.size() < 3) break;
    refit(points, next, best);
  }
  if (best.normal.dot(upUnit) < 0) {
    best.normal = -best.normal;
    best.offset = -best.offset;
  }
  // Reported against the full band, as RANSAC counted them.
  best.inliers = 0;
  for (int i = 0; i < n; ++i)
    best.inliers += std::abs(best.normal.dot(points[i]) + best.offset) < options.inlierDistance;
  return best;
}

}  // namespace

PlaneFit fitGroundPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                        const PlaneFitOptions& options) {
  return fitPlane(points, up, options, [](const Eigen::Vector3d&, double) { return true; });
}

GroundBelowCameras fitGroundBelowCameras(const std::vector<Eigen::Vector3d>& points,
                                         const std::vector<Eigen::Vector3d>& cameras,
                                         const Eigen::Vector3d& up, const PlaneFitOptions& options,
                                         double maxCameraTiltDeg) {
  // Whether every camera stands more than `clearance` above the plane.
  auto camerasClear = [&](const Eigen::Vector3d& normal, double offset, double clearance) {
    for (const Eigen::Vector3d& c : cameras)
      if (normal.dot(c) + offset <= clearance) return false;
    return true;
  };
  // RANSAC's candidates must clear the inlier band; the joint plane need only stay under the
  // cameras: the band is a fraction of the scene depth, over a metre when the ground points lie
  // at a façade 60 m away (Sceaux Castle), and a camera 1.4 m over a plane that fits the ground
  // and the cameras is no wall top.
  auto belowAll = [&](const Eigen::Vector3d& normal, double offset) {
    return camerasClear(normal, offset, options.inlierDistance);
  };
  GroundBelowCameras result;
  result.plane = fitPlane(points, up, options, belowAll);
  if (!result.plane.found || cameras.size() < 2) return result;
  std::vector<int> allCameras(cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) allCameras[i] = static_cast<int>(i);
  Eigen::Vector3d cameraMean;
  const Eigen::Matrix3d cameraCov = covariance(cameras, allCameras, cameraMean);
  PlaneFit joint = result.plane;
  for (int pass = 0; pass < 3; ++pass) {
    const std::vector<int> inliers = within(points, joint, 0.25 * options.inlierDistance);
    if (inliers.size() < 3) return result;
    Eigen::Vector3d pointMean;
    const Eigen::Matrix3d pointCov = covariance(points, inliers, pointMean);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(pointCov + cameraCov);
    Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
    if (n.dot(up) < 0) n = -n;
    joint.normal = n;
    joint.offset = -n.dot(pointMean);
  }
  result.pointsOnlyTiltDeg =
      std::acos(std::clamp(joint.normal.dot(result.plane.normal), -1.0, 1.0)) * 180.0 / M_PI;
  if (result.pointsOnlyTiltDeg > maxCameraTiltDeg || !camerasClear(joint.normal, joint.offset, 0.0))
    return result;
  joint.inliers = static_cast<int>(within(points, joint, options.inlierDistance).size());
  result.plane = joint;
  result.camerasUsed = true;
  return result;
}

}  // namespace pluvia::sfm
