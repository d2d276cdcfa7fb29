#pragma once
// From a COLMAP model to pluvia's camera path and metric sparse points.
//
// Conventions: COLMAP stores camera-from-world poses (x_cam = R x + t) with the camera looking
// along +Z and +Y down; pluvia (geometry/camera.h) stores worldFromCamera with the camera looking
// along -Z and +Y up, in a metric world whose ground is y = 0 with +Y up. The camera axes differ by
// F = diag(1, -1, -1), so worldFromCamera = Q * R^T * F and the centre is s * Q * (-R^T t) + T,
// where (s, Q, T) is the similarity from model units to pluvia's world chosen from a scale hint.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "sfm/colmap_model.h"
#include "sfm/vertical_lines.h"

namespace pluvia::sfm {

// x_world = scale * rotation * x_model + translationMeters.
struct ModelToWorld {
  double scale = 1.0;  // metres per model unit
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translationMeters = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& model) const {
    return scale * (rotation * model) + translationMeters;
  }
};

// One image's pose as a pluvia Camera (intrinsics from `camera`; distortion is dropped), mapped
// into the world by `toWorld`.
Camera pluviaCameraFromColmap(const ColmapCamera& camera, const ColmapImage& image,
                              const ModelToWorld& toWorld = {});

// How metric scale is chosen; at most one should be set. Neither leaves the model's own units.
struct SfmScaleHint {
  // (a) The cameras' mean height above the ground. The ground plane is fitted to the sparse points
  // below every camera, its tilt along the path taken from the cameras riding at one height
  // (ground_plane.h fitGroundBelowCameras); +Y is the vertical of the façades' lines when the
  // images show enough of them (vertical_lines.h), else the ground's normal; the ground passes
  // through the origin below the first camera (y = 0 there) and may slope (groundNormal).
  std::optional<double> cameraHeightMeters;
  // (b) The median depth of the points the first registered frame sees. The world is then
  // levelled by the cameras' mean up axis and the first camera sits at the origin (y = 0 is the
  // first camera's height, not the ground).
  std::optional<double> firstFrameMedianDepthMeters;
};

struct SfmOptions {
  SfmScaleHint scale;
  // Below this camera-centre spread / median scene depth the clip is a pan from a tripod: depth
  // from SfM is unreliable and the caller should fall back to manual layers.
  double minBaselineOverDepth = 0.02;
  double minRegisteredFraction = 0.5;  // of the frames handed over
  int minRegisteredFrames = 3;
  // Ground-plane RANSAC inlier band, as a fraction of the median scene depth.
  double groundInlierFractionOfDepth = 0.02;
  double groundMaxTiltDeg = 30.0;
  // The cues that check gravity and scale; a cue outside its bound is a warning with the numbers
  // (SfmReconstruction::warnings), not a failure: the tracking may still be right.
  VerticalLineOptions verticalLines;
  double maxGroundTiltFromVerticalDeg = 6.0;  // a steep street; beyond, the model may be bent
  double maxCameraHeightSpread = 0.1;         // standard deviation / mean camera height
  // A model bent this many times past those bounds (heights spreading 30 %, the ground 18 deg off
  // the façades) is refused rather than warned about: its scale and depth would be wrong.
  double maxUsableBentness = 3.0;
  // Where façade lines show buildings, the points' 95th-percentile height above the ground should
  // exceed this many camera heights (a one-storey house is about 2 camera heights tall).
  double minStructureOverCameraHeight = 1.5;
  double maxCameraSpeedMetersPerSecond = 40.0;  // between registered frames
  double framesPerSecond = 0.0;                 // the clip's; 0: unknown (photos), no speed cue
};

// ImplausibleCamera and Bent are set by the caller (clip_tracking.h), not by
// reconstructionFromColmap.
enum class SfmStatus { Ok, TooFewRegistered, NoParallax, NoGroundPlane, ImplausibleCamera, Bent };
// "ok", "too_few_registered", "no_parallax", "no_ground_plane", "implausible_camera", "bent".
const char* sfmStatusName(SfmStatus status);

// A registered clip frame.
struct SfmKeyframe {
  int64_t frame = 0;
  std::string imageName;
  Camera camera;                         // metric, pluvia convention
  std::vector<int> visiblePoints;        // indices into SfmReconstruction::pointsMeters it observes
  double heightAboveGroundMeters = NAN;  // along the ground's normal; NaN without a ground
};

struct SfmReconstruction {
  SfmStatus status = SfmStatus::Ok;
  std::string message;                 // why the status is not Ok (or notes such as "unscaled")
  Camera intrinsics;                   // size, focal length, principal point of the shared camera
  CameraPath path;                     // keys at the registered frames; frames between interpolate
  std::vector<SfmKeyframe> keyframes;  // increasing frame order
  std::vector<Eigen::Vector3d> pointsMeters;  // sparse points in pluvia's world
  ModelToWorld modelToWorld;
  int frameCount = 0;       // frames handed over (name -> frame entries)
  int registeredCount = 0;  // of those, registered by the mapper
  double registeredFraction = 0.0;
  double meanReprojectionErrorPx = 0.0;
  double baselineOverDepth = 0.0;  // camera-centre bounding-box diagonal / median scene depth
  double medianDepthMeters = 0.0;  // over all observations, after scaling
  bool groundAtYZero = false;      // the world was placed on a fitted ground plane (y = 0)
  // The fitted ground in the world, groundNormal . x + groundOffsetMeters = 0 (with
  // groundAtYZero; +Y and 0 otherwise). It tilts from +Y where the street slopes.
  Eigen::Vector3d groundNormal = Eigen::Vector3d::UnitY();
  double groundOffsetMeters = 0.0;
  // Where +Y comes from: "facade lines", "ground plane" or "camera up" (the cameras' mean up).
  std::string gravitySource = "camera up";
  int verticalLineCount = 0;               // façade lines that agree on the vertical
  double groundTiltFromVerticalDeg = NAN;  // the ground's normal from the lines' vertical
  double structureHeightMeters = NAN;      // points' 95th-percentile height above the ground
  double cameraHeightSpread = NAN;         // standard deviation / mean of the cameras' heights
  double medianCameraSpeedMetersPerSecond = NAN;  // with SfmOptions::framesPerSecond
  // Cues that disagree with the gravity or the scale, each with its numbers (scale_cues.h).
  std::vector<std::string> warnings;
  bool ok() const { return status == SfmStatus::Ok; }
};

// Builds the metric reconstruction. `frameOfImage` maps COLMAP image names to clip frame numbers;
// registered images absent from it are ignored. Never throws for weak reconstructions: it returns
// a status and message the caller uses to fall back (TooFewRegistered leaves path empty;
// NoParallax and NoGroundPlane keep the poses, unscaled, since rotations are still right).
// `imageFolder` holds the images by their model names, for the façade lines; empty: none.
SfmReconstruction reconstructionFromColmap(const ColmapModel& model,
                                           const std::map<std::string, int64_t>& frameOfImage,
                                           const SfmOptions& options = {},
                                           const std::filesystem::path& imageFolder = {});

}  // namespace pluvia::sfm
