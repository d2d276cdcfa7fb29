#include "sfm/sfm_poses.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include <Eigen/Geometry>

#include "sfm/ground_plane.h"
#include "sfm/scale_cues.h"
#include "util/median.h"

namespace pluvia::sfm {
namespace {

// COLMAP camera axes (x right, y down, z forward) <-> pluvia camera axes (x right, y up, z back).
const Eigen::Matrix3d kFlipYZ = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();

// Depths (COLMAP z in the camera) of the points an image observes.
std::vector<double> observedDepths(const ColmapModel& model, const ColmapImage& image) {
  std::vector<double> depths;
  const Eigen::Matrix3d r = image.cameraFromWorld();
  for (const auto& obs : image.observations) {
    if (obs.point3DId < 0) continue;
    auto it = model.points.find(obs.point3DId);
    if (it == model.points.end()) continue;
    double z = (r * it->second.xyz + image.tvec).z();
    if (z > 0) depths.push_back(z);
  }
  return depths;
}

// A rotation taking `up` to +Y and the horizontal part of `forward` to -Z, so that the first
// camera starts out looking along pluvia's default heading.
Eigen::Matrix3d levelRotation(const Eigen::Vector3d& up, const Eigen::Vector3d& forward,
                              const Eigen::Vector3d& right) {
  Eigen::Vector3d y = up.normalized();
  Eigen::Vector3d f = forward - forward.dot(y) * y;
  // Looking straight down or up: the camera's right axis still fixes the heading.
  if (f.norm() < 1e-6) f = y.cross(right);
  f.normalize();
  Eigen::Vector3d z = -f;
  Eigen::Vector3d x = y.cross(z).normalized();
  Eigen::Matrix3d q;
  q.row(0) = x.transpose();
  q.row(1) = y.transpose();
  q.row(2) = z.transpose();
  return q;
}

std::string fixed(double value, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << std::fixed << value;
  return s.str();
}

}  // namespace

Camera pluviaCameraFromColmap(const ColmapCamera& camera, const ColmapImage& image,
                              const ModelToWorld& toWorld) {
  Camera out;
  out.width = camera.width;
  out.height = camera.height;
  out.focalPx = camera.focalPx();
  out.cx = camera.cxPx();
  out.cy = camera.cyPx();
  out.worldFromCamera = toWorld.rotation * image.cameraFromWorld().transpose() * kFlipYZ;
  out.positionMeters = toWorld.apply(image.centre());
  return out;
}

const char* sfmStatusName(SfmStatus status) {
  switch (status) {
    case SfmStatus::Ok:
      return "ok";
    case SfmStatus::TooFewRegistered:
      return "too_few_registered";
    case SfmStatus::NoParallax:
      return "no_parallax";
    case SfmStatus::NoGroundPlane:
      return "no_ground_plane";
    case SfmStatus::ImplausibleCamera:
      return "implausible_camera";
    case SfmStatus::Bent:
      return "bent";
  }
  return "ok";
}

SfmReconstruction reconstructionFromColmap(const ColmapModel& model,
                                           const std::map<std::string, int64_t>& frameOfImage,
                                           const SfmOptions& options,
                                           const std::filesystem::path& imageFolder) {
  SfmReconstruction result;
  result.frameCount = static_cast<int>(frameOfImage.size());
  result.meanReprojectionErrorPx = model.meanReprojectionErrorPx();

  // Registered images the caller knows, in frame order.
  std::vector<std::pair<int64_t, const ColmapImage*>> registered;
  for (const auto& [id, image] : model.images) {
    auto it = frameOfImage.find(image.name);
    if (it != frameOfImage.end()) registered.push_back({it->second, &image});
  }
  std::sort(registered.begin(), registered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  result.registeredCount = static_cast<int>(registered.size());
  result.registeredFraction =
      result.frameCount > 0 ? static_cast<double>(registered.size()) / result.frameCount : 0.0;
  if (result.registeredCount < options.minRegisteredFrames ||
      result.registeredFraction < options.minRegisteredFraction || model.cameras.empty()) {
    result.status = SfmStatus::TooFewRegistered;
    result.message = "COLMAP registered only " + std::to_string(result.registeredCount) + " of " +
                     std::to_string(result.frameCount) +
                     " frames: too little parallax or texture for camera tracking";
    return result;
  }
  const ColmapCamera& colmapCamera = model.cameras.at(registered.front().second->cameraId);

  // Scene depth and camera spread, in model units.
  std::vector<double> allDepths;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  Eigen::Vector3d upSum = Eigen::Vector3d::Zero(), centreSum = Eigen::Vector3d::Zero();
  for (const auto& [frame, image] : registered) {
    std::vector<double> d = observedDepths(model, *image);
    allDepths.insert(allDepths.end(), d.begin(), d.end());
    Eigen::Vector3d c = image->centre();
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
    centreSum += c;
    // COLMAP's camera "up" is -y.
    upSum += image->cameraFromWorld().transpose() * Eigen::Vector3d(0, -1, 0);
  }
  const double medianDepthModel = median(allDepths);
  const Eigen::Vector3d meanCentre = centreSum / static_cast<double>(registered.size());
  const Eigen::Vector3d up = upSum.normalized();
  result.baselineOverDepth = medianDepthModel > 0 ? (hi - lo).norm() / medianDepthModel : 0.0;

  const ColmapImage& first = *registered.front().second;
  const Eigen::Matrix3d firstR = first.cameraFromWorld();
  const Eigen::Vector3d firstForward = firstR.transpose() * Eigen::Vector3d(0, 0, 1);
  const Eigen::Vector3d firstRight = firstR.transpose() * Eigen::Vector3d(1, 0, 0);

  // Default: levelled by the mean camera up, first camera at the origin, model units.
  ModelToWorld toWorld;
  toWorld.rotation = levelRotation(up, firstForward, firstRight);
  bool scaled = false;
  bool groundPlaced = false;

  if (result.baselineOverDepth < options.minBaselineOverDepth) {
    result.status = SfmStatus::NoParallax;
    result.message = "camera baseline is " + fixed(result.baselineOverDepth, 4) +
                     " of the median scene depth (below " + fixed(options.minBaselineOverDepth, 4) +
                     "): a pan without travel gives no depth";
  } else if (options.scale.cameraHeightMeters) {
    // The vertical: the façades' lines where the images show enough of them.
    VerticalLineGravity lines;
    if (!imageFolder.empty()) lines = verticalFromLines(model, imageFolder, options.verticalLines);
    const Eigen::Vector3d vertical = lines.found ? lines.upModel : up;
    std::vector<Eigen::Vector3d> below, centres;
    for (const auto& [frame, image] : registered) centres.push_back(image->centre());
    for (const auto& [id, point] : model.points)
      if (vertical.dot(point.xyz - meanCentre) < 0) below.push_back(point.xyz);
    PlaneFitOptions planeOptions;
    planeOptions.inlierDistance = options.groundInlierFractionOfDepth * medianDepthModel;
    planeOptions.maxTiltDeg = options.groundMaxTiltDeg;
    const PlaneFit plane = fitGroundBelowCameras(below, centres, vertical, planeOptions).plane;
    double meanHeight = 0.0;
    for (const Eigen::Vector3d& c : centres) meanHeight += plane.normal.dot(c) + plane.offset;
    meanHeight /= static_cast<double>(centres.size());
    if (!plane.found || meanHeight <= 0.0) {
      result.status = SfmStatus::NoGroundPlane;
      result.message = "no ground plane found below the cameras among " +
                       std::to_string(below.size()) +
                       " sparse points; cannot scale by camera height";
    } else {
      toWorld.scale = *options.scale.cameraHeightMeters / meanHeight;
      const Eigen::Vector3d worldUp = lines.found ? lines.upModel : plane.normal;
      toWorld.rotation = levelRotation(worldUp, firstForward, firstRight);
      // The origin is the ground below the first camera along +Y, the first camera above it.
      const double firstHeight = plane.normal.dot(first.centre()) + plane.offset;
      const Eigen::Vector3d foot =
          first.centre() - firstHeight / plane.normal.dot(worldUp) * worldUp;
      toWorld.translationMeters = -toWorld.scale * (toWorld.rotation * foot);
      // n . x + d = 0 in the model is n_w . y - n_w . T + s d = 0 in the world (y = s Q x + T).
      result.groundNormal = toWorld.rotation * plane.normal;
      result.groundOffsetMeters =
          toWorld.scale * plane.offset - result.groundNormal.dot(toWorld.translationMeters);
      result.gravitySource = lines.found ? "facade lines" : "ground plane";
      result.verticalLineCount = lines.inliers;
      if (lines.found)
        result.groundTiltFromVerticalDeg =
            std::acos(std::clamp(plane.normal.dot(lines.upModel), -1.0, 1.0)) * 180.0 / M_PI;
      else if (!imageFolder.empty())
        result.message = "gravity from the ground plane: " + lines.message;
      scaled = true;
      groundPlaced = true;
    }
  } else if (options.scale.firstFrameMedianDepthMeters) {
    double firstMedian = median(observedDepths(model, first));
    if (firstMedian > 0.0) {
      toWorld.scale = *options.scale.firstFrameMedianDepthMeters / firstMedian;
      scaled = true;
    } else {
      result.message = "the first registered frame sees no points; left unscaled";
    }
  } else {
    result.message = "no scale hint: poses are in COLMAP's arbitrary units";
  }
  // Without a fitted ground the first camera sits at the origin.
  if (!groundPlaced)
    toWorld.translationMeters = -toWorld.scale * (toWorld.rotation * first.centre());
  if (!scaled && result.status == SfmStatus::Ok && result.message.empty())
    result.message = "left unscaled";
  result.modelToWorld = toWorld;
  result.groundAtYZero = groundPlaced;
  result.medianDepthMeters = medianDepthModel * toWorld.scale;

  // Points, re-indexed densely.
  std::unordered_map<int64_t, int> pointIndex;
  result.pointsMeters.reserve(model.points.size());
  for (const auto& [id, point] : model.points) {
    pointIndex[id] = static_cast<int>(result.pointsMeters.size());
    result.pointsMeters.push_back(toWorld.apply(point.xyz));
  }

  std::vector<CameraPathKey> keys;
  for (const auto& [frame, image] : registered) {
    SfmKeyframe key;
    key.frame = frame;
    key.imageName = image->name;
    key.camera = pluviaCameraFromColmap(model.cameras.at(image->cameraId), *image, toWorld);
    if (groundPlaced)
      key.heightAboveGroundMeters =
          result.groundNormal.dot(key.camera.positionMeters) + result.groundOffsetMeters;
    for (const auto& obs : image->observations) {
      auto it = pointIndex.find(obs.point3DId);
      if (obs.point3DId >= 0 && it != pointIndex.end()) key.visiblePoints.push_back(it->second);
    }
    keys.push_back({static_cast<double>(frame), key.camera.positionMeters,
                    Eigen::Quaterniond(key.camera.worldFromCamera)});
    result.keyframes.push_back(std::move(key));
  }
  result.intrinsics = pluviaCameraFromColmap(colmapCamera, first, toWorld);
  result.path = CameraPath::fromRotations(result.intrinsics, std::move(keys));
  if (scaled) checkScaleCues(result, options);
  return result;
}

}  // namespace pluvia::sfm
