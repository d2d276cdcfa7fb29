#include "sfm/ground_plane.h"

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

}  // namespace

PlaneFit fitGroundPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                        const PlaneFitOptions& options) {
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

}  // namespace pluvia::sfm
