#include "sfm/vertical_lines.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace pluvia::sfm {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

struct LinePlane {
  Eigen::Vector3d normalModel;  // unit normal of the interpretation plane, model coordinates
  double lengthPx = 0.0;
};

// COLMAP's radial coefficients (k1, k2) for the models that have them; others count as
// undistorted (the perspective models pluvia asks COLMAP for are SIMPLE_RADIAL or RADIAL).
Eigen::Vector2d radialCoefficients(const ColmapCamera& camera) {
  if (camera.model == "SIMPLE_RADIAL" && camera.params.size() >= 4) return {camera.params[3], 0.0};
  if (camera.model == "RADIAL" && camera.params.size() >= 5)
    return {camera.params[3], camera.params[4]};
  return {0.0, 0.0};
}

// The ray (COLMAP camera coordinates, z forward) through pixel (x, y), radial distortion undone
// by fixed-point iteration (a handful of steps converge for the small k of phone lenses).
Eigen::Vector3d pixelRay(const ColmapCamera& camera, const Eigen::Vector2d& k, double xPx,
                         double yPx) {
  const double f = camera.focalPx();
  const Eigen::Vector2d distorted((xPx - camera.cxPx()) / f, (yPx - camera.cyPx()) / f);
  Eigen::Vector2d u = distorted;
  for (int i = 0; i < 8; ++i) {
    const double r2 = u.squaredNorm();
    u = distorted / (1.0 + k.x() * r2 + k.y() * r2 * r2);
  }
  return Eigen::Vector3d(u.x(), u.y(), 1.0);
}

// Near-vertical segments of one image as planes in model coordinates.
void collectCandidates(const ColmapModel& model, const ColmapImage& image, const cv::Mat& grey,
                       const Eigen::Vector3d& upPrior, const VerticalLineOptions& options,
                       std::vector<LinePlane>& planes) {
  const ColmapCamera& camera = model.cameras.at(image.cameraId);
  const Eigen::Vector2d k = radialCoefficients(camera);
  // COLMAP's pixel coordinates are those of the image it saw; a file of another size (a proxy)
  // is scaled to it.
  const double sx = camera.width / static_cast<double>(grey.cols);
  const double sy = camera.height / static_cast<double>(grey.rows);
  const double minLength = options.minLengthFraction * std::hypot(grey.cols, grey.rows);
  const Eigen::Matrix3d modelFromCamera = image.cameraFromWorld().transpose();
  const double maxSin = std::sin(options.candidateMaxDeg * kDegToRad);
  std::vector<cv::Vec4f> segments;
  cv::createLineSegmentDetector(cv::LSD_REFINE_STD)->detect(grey, segments);
  for (const cv::Vec4f& s : segments) {
    const double length = std::hypot(s[2] - s[0], s[3] - s[1]);
    if (length < minLength) continue;
    // LSD's endpoints are in pixel-corner coordinates; COLMAP's pixel centres are at +0.5.
    const Eigen::Vector3d a = pixelRay(camera, k, (s[0] + 0.5) * sx, (s[1] + 0.5) * sy);
    const Eigen::Vector3d b = pixelRay(camera, k, (s[2] + 0.5) * sx, (s[3] + 0.5) * sy);
    const Eigen::Vector3d normal = (modelFromCamera * a.cross(b)).normalized();
    if (std::abs(normal.dot(upPrior)) > maxSin) continue;
    planes.push_back({normal, length});
  }
}

// The direction the planes' normals are most nearly perpendicular to, weighted by length.
Eigen::Vector3d weightedNullDirection(const std::vector<LinePlane>& planes,
                                      const std::vector<int>& inliers,
                                      const Eigen::Vector3d& sign) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : inliers)
    scatter += planes[i].lengthPx * planes[i].normalModel * planes[i].normalModel.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d up = solver.eigenvectors().col(0).normalized();
  return up.dot(sign) < 0 ? -up : up;
}

std::vector<int> inliersOf(const std::vector<LinePlane>& planes, const Eigen::Vector3d& up,
                           double maxSin, double* lengthSum = nullptr) {
  std::vector<int> inliers;
  double sum = 0.0;
  for (int i = 0; i < static_cast<int>(planes.size()); ++i)
    if (std::abs(planes[i].normalModel.dot(up)) < maxSin) {
      inliers.push_back(i);
      sum += planes[i].lengthPx;
    }
  if (lengthSum) *lengthSum = sum;
  return inliers;
}

}  // namespace

VerticalLineGravity verticalFromLines(const ColmapModel& model,
                                      const std::filesystem::path& imageFolder,
                                      const VerticalLineOptions& options) {
  VerticalLineGravity result;
  Eigen::Vector3d upPrior = Eigen::Vector3d::Zero();
  for (const auto& [id, image] : model.images)
    upPrior += image.cameraFromWorld().transpose() * Eigen::Vector3d(0, -1, 0);  // COLMAP: y down
  if (upPrior.norm() < 1e-9) {
    result.message = "no registered images";
    return result;
  }
  upPrior.normalize();

  std::vector<LinePlane> planes;
  std::vector<int> imageOfPlane;
  for (const auto& [id, image] : model.images) {
    const cv::Mat grey = cv::imread((imageFolder / image.name).string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) continue;
    collectCandidates(model, image, grey, upPrior, options, planes);
    imageOfPlane.resize(planes.size(), id);
  }
  result.candidates = static_cast<int>(planes.size());
  if (result.candidates < options.minInliers) {
    result.message = fmt::format("{} near-vertical lines in the images (at least {} needed)",
                                 result.candidates, options.minInliers);
    return result;
  }

  const double maxSin = std::sin(options.inlierMaxDeg * kDegToRad);
  const double minCosPrior = std::cos(options.maxDeviationFromPriorDeg * kDegToRad);
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, result.candidates - 1);
  Eigen::Vector3d best = upPrior;
  double bestScore = -1.0;
  for (int it = 0; it < options.iterations; ++it) {
    const int a = pick(rng), b = pick(rng);
    Eigen::Vector3d up = planes[a].normalModel.cross(planes[b].normalModel);
    // Nearly the same plane (two edges of one window frame close together): no direction.
    if (up.norm() < std::sin(2.0 * kDegToRad)) continue;
    up.normalize();
    if (up.dot(upPrior) < 0) up = -up;
    if (up.dot(upPrior) < minCosPrior) continue;
    double score = 0.0;
    inliersOf(planes, up, maxSin, &score);
    if (score > bestScore) {
      bestScore = score;
      best = up;
    }
  }
  std::vector<int> inliers = inliersOf(planes, best, maxSin);
  for (int refine = 0; refine < 3 && inliers.size() >= 2; ++refine) {
    best = weightedNullDirection(planes, inliers, upPrior);
    inliers = inliersOf(planes, best, maxSin);
  }
  result.inliers = static_cast<int>(inliers.size());
  if (result.inliers < options.minInliers) {
    result.message = fmt::format(
        "only {} of {} near-vertical lines share a vanishing direction (at least {} needed)",
        result.inliers, result.candidates, options.minInliers);
    return result;
  }
  double sumSquares = 0.0;
  std::vector<int> images;
  for (int i : inliers) {
    const double residual = std::asin(std::abs(planes[i].normalModel.dot(best)));
    sumSquares += residual * residual;
    images.push_back(imageOfPlane[i]);
  }
  std::sort(images.begin(), images.end());
  result.imagesWithLines =
      static_cast<int>(std::unique(images.begin(), images.end()) - images.begin());
  result.rmsResidualDeg = std::sqrt(sumSquares / result.inliers) / kDegToRad;
  result.upModel = best;
  result.found = true;
  return result;
}

}  // namespace pluvia::sfm
